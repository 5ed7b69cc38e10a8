# SPDX-License-Identifier: LGPL-2.1-or-later
"""Sketch curves: the paper's curves per operator, with its labels and start/end order."""

import cadquery as cq
import numpy as np
import pytest
import round_fixtures as knob

from Sketch2CADWorkbench.brep.faces import base_face_index, resolve_face
from Sketch2CADWorkbench.brep.operators import build, make_box
from Sketch2CADWorkbench.brep.protocol import (
    AddSubPrism,
    Bevel,
    Box,
    Extrude,
    FaceRef,
    Mode,
    OperationError,
    Protocol,
    Surface,
    Sweep,
)
from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.sketch.curves import operation_curves, outline_corners
from Sketch2CADWorkbench.sketch.labels import (
    BEVEL_L,
    BEVEL_L_PRIME,
    END,
    EXTRUDE_OFFSET,
    EXTRUDE_PROFILE,
    PROFILE,
    START,
)

BOX = make_box(Box((40.0, 30.0, 20.0)))
TOP = FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0))
VIEW = np.array([-0.5, -0.6, -0.62])


def _ends(curves, label):
    return [c.points for c in curves if c.label == label]


def test_extrude_offset_curve_is_the_moved_face_and_profiles_its_side_edges():
    curves = operation_curves(BOX, Extrude(TOP, 7.0), VIEW)
    offset = np.concatenate(_ends(curves, EXTRUDE_OFFSET))
    assert len(_ends(curves, EXTRUDE_OFFSET)) == 4 and np.allclose(offset[:, 2], 17.0)
    assert np.allclose(np.abs(offset[:, :2]), [20.0, 15.0])
    sides = _ends(curves, EXTRUDE_PROFILE)
    assert len(sides) == 4
    for s in sides:
        assert np.allclose(s[1] - s[0], [0, 0, 7.0])
    assert all(c.relevant == (c.label == EXTRUDE_OFFSET) for c in curves)


def test_a_circular_outline_has_no_side_edge_at_its_seam():
    disc = cq.Solid.makeCylinder(10.0, 5.0)
    top = next(f for f in disc.Faces() if f.geomType() == "PLANE" and f.Center().z > 4)
    assert outline_corners(top) == []
    curves = operation_curves(disc, Extrude(FaceRef((0, 0, 5.0), (0, 0, 1.0)), 3.0), VIEW)
    assert [c.label for c in curves] == [EXTRUDE_OFFSET]


def test_bevel_curves_are_l_on_f_and_l_moved_along_the_crease():
    profile = ((20.0, 5.0, 10.0), (20.0, 10.0, 10.0), (15.0, 15.0, 10.0), (10.0, 15.0, 10.0))
    op = Bevel(TOP, (20.0, 15.0, 10.0), (20.0, 15.0, -10.0), profile)
    curves = operation_curves(BOX, op, VIEW)
    (l_curve,), (l_prime,) = _ends(curves, BEVEL_L), _ends(curves, BEVEL_L_PRIME)
    assert np.allclose(l_curve[[0, -1]], [profile[0], profile[3]])
    assert np.allclose(l_prime - l_curve, [0, 0, -20.0])


def test_a_profile_across_a_rim_is_drawn_again_across_the_rim_and_along_an_edge_at_its_end():

    op = knob.rim(3.0)
    curves = operation_curves(build(Protocol(knob.BASE, (knob.KNOB,))), op, VIEW)
    (l_curve,), (l_prime,) = _ends(curves, BEVEL_L), _ends(curves, BEVEL_L_PRIME)
    assert np.allclose(l_curve[[0, -1]], [op.profile[0], op.profile[3]])
    # turned half round the knob's axis: x and y change sign, heights stay
    assert np.allclose(l_prime[:, :2], -l_curve[:, :2]) and np.allclose(
        l_prime[:, 2], l_curve[:, 2]
    )
    assert np.allclose(np.hypot(*l_prime[0, :2]), knob.R - 3.0) and l_prime[0, 2] == knob.TOP
    edge = knob.top_edge()  # at x = 0 on the plate's 60 mm front edge: again at its end
    curves = operation_curves(build(Protocol(knob.BASE, ())), edge, VIEW)
    (l_curve,), (l_prime,) = _ends(curves, BEVEL_L), _ends(curves, BEVEL_L_PRIME)
    assert np.allclose(np.abs(l_prime[:, 0] - l_curve[:, 0]), 30.0)


@pytest.mark.parametrize("mode", [Mode.ADD, Mode.SUBTRACT])
def test_prism_start_and_end_curves_are_ordered_along_the_face_normal(mode):
    poly = ((-5.0, -5.0, 10.0), (5.0, -5.0, 10.0), (0.0, 6.0, 10.0))
    curves = operation_curves(BOX, AddSubPrism(TOP, poly, 8.0, mode), VIEW)
    start, end = (np.concatenate(_ends(curves, k)) for k in (START, END))
    assert len(_ends(curves, START)) == len(_ends(curves, END)) == len(_ends(curves, PROFILE)) == 3
    assert np.all(start[:, 2] < end[:, 2])  # start first along n_f, whatever the option
    base = start if mode is Mode.ADD else end
    assert np.allclose(base[:, 2], 10.0)  # the base polygon lies on f
    relevant = [c for c in curves if c.relevant]  # the base polygon, for the view filter
    assert len(relevant) == 3 and all(np.allclose(c.points[:, 2], 10.0) for c in relevant)
    assert {c.label for c in relevant} == {START if mode is Mode.ADD else END}


def test_sweep_profile_lines_are_the_silhouette_of_a_cylinder():
    op = Sweep(TOP, (0.0, 0.0, 10.0), 6.0, 6.0, 12.0, ((6.0, 4.0), (6.0, 8.0)), Mode.ADD)
    curves = operation_curves(BOX, op, VIEW)
    camera = OrthoCamera((0.0, 0.0, 15.0), tuple(VIEW), (0.0, 0.0, 1.0), 30.0)
    # The cylinder's outline across its projected axis, from a dense point cloud.
    t, h = np.meshgrid(np.linspace(0, 2 * np.pi, 720), np.linspace(0, 12, 25))
    cloud = np.stack([6 * np.cos(t), 6 * np.sin(t), 10 + h], axis=-1).reshape(-1, 3)
    axis_px = camera.project(np.array([[0, 0, 10.0], [0, 0, 22.0]]))[0]
    a = (axis_px[1] - axis_px[0]) / np.linalg.norm(axis_px[1] - axis_px[0])
    across = np.array([-a[1], a[0]])
    reach = (camera.project(cloud)[0] - axis_px[0]) @ across
    for profile in _ends(curves, PROFILE):
        off = (camera.project(profile)[0] - axis_px[0]) @ across
        assert np.allclose(np.abs(off), np.abs(reach).max(), atol=1e-3)
    start, end = _ends(curves, START), _ends(curves, END)
    assert np.allclose(start[0][:, 2], 10.0) and np.allclose(end[0][:, 2], 22.0)


def test_subtracted_sweep_starts_with_the_circle_inside_the_solid():
    op = Sweep(TOP, (0.0, 0.0, 10.0), 6.0, 4.0, 5.0, ((5.5, 2.0), (4.5, 4.0)), Mode.SUBTRACT)
    curves = operation_curves(BOX, op, VIEW)
    (start,), (end,) = _ends(curves, START), _ends(curves, END)
    assert np.allclose(start[:, 2], 5.0) and np.allclose(np.linalg.norm(start[:, :2], axis=1), 4.0)
    assert np.allclose(end[:, 2], 10.0) and np.allclose(np.linalg.norm(end[:, :2], axis=1), 6.0)
    assert [c.relevant for c in curves if c.closed] == [False, True]


def test_base_face_index_names_the_resolved_face():
    i = base_face_index(BOX, resolve_face(BOX, TOP).face)
    assert BOX.Faces()[i].Center().z == pytest.approx(10.0)


def test_base_face_index_matches_the_face_in_either_orientation_and_refuses_others():
    faces = BOX.Faces()
    assert base_face_index(BOX, cq.Face(faces[3].wrapped.Reversed())) == 3
    with pytest.raises(ValueError, match="not a face of the solid"):
        base_face_index(BOX, make_box(Box((40.0, 30.0, 20.0))).Faces()[3])


def test_a_circle_wider_than_the_curved_face_it_stands_on_is_refused_as_an_operation():
    # what a reading's score needs (interpret refuses that operator, saying why) rather
    # than a bare ValueError that stopped the whole step
    post = cq.Solid.makeCylinder(5.0, 10.0)
    side = FaceRef((5.0, 0.0, 5.0), (1.0, 0.0, 0.0), Surface.CYLINDER)
    peg = Sweep(side, (5.0, 0.0, 5.0), 6.0, 6.0, 4.0, ((6.0, 4 / 3), (6.0, 8 / 3)))
    with pytest.raises(OperationError, match="reaches past the side of the curved face"):
        operation_curves(post, peg, np.array([-1.0, 0.2, -0.3]))
