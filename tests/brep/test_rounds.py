# SPDX-License-Identifier: LGPL-2.1-or-later
"""Rounds and chamfers across straight edges, circular rims, tangent chains and a face's
outline give the analytically expected solids, and refuse what OCCT cannot build."""

import math

import numpy as np
import pytest
from round_fixtures import (
    BASE,
    DISK,
    KNOB,
    TOP,
    R,
    knob_volume,
    knob_with,
    quarter,
    revolved,
    rim,
    rounded_box,
    top_edge,
)

from Sketch2CADWorkbench.brep.faces import OperationError
from Sketch2CADWorkbench.brep.geometry import bezier
from Sketch2CADWorkbench.brep.operators import apply_operation, build, make_box, replay
from Sketch2CADWorkbench.brep.protocol import Bevel, EdgeSet, FaceRef, Mode, Protocol, Sweep
from Sketch2CADWorkbench.brep.rounds import edge_faces, tangent_chain


def test_a_fillet_around_a_rim_removes_the_revolved_corner():
    r = 3.0
    area = r * r * (1 - math.pi / 4)
    # the corner region's centroid lies (10 - 3 pi) / (12 - 3 pi) r in from the rim
    centroid = R - r * (10 - 3 * math.pi) / (12 - 3 * math.pi)
    removed = knob_volume() - knob_with(rim(r, radius=r)).Volume()
    assert removed == pytest.approx(revolved(area, centroid), rel=1e-6)


def test_a_chamfer_measures_its_first_distance_on_f():
    d1, d2 = 2.0, 3.0
    removed = knob_volume() - knob_with(rim(distances=(d1, d2))).Volume()
    # the triangle's legs: d1 across the top disk, d2 down the side
    assert removed == pytest.approx(revolved(d1 * d2 / 2, R - d1 / 3), rel=1e-6)


def test_a_freeform_profile_is_revolved_around_the_rim():
    op = rim(3.0)
    ctrl = np.array(op.profile)
    region = np.vstack([[R, TOP], bezier(ctrl, np.linspace(0, 1, 2001))[:, [0, 2]]])
    x, y = region[:, 0], region[:, 1]
    cross = x * np.roll(y, -1) - np.roll(x, -1) * y
    area = abs(cross.sum()) / 2
    cx = abs((cross * (x + np.roll(x, -1))).sum() / (6 * cross.sum() / 2))
    removed = knob_volume() - knob_with(op).Volume()
    assert removed == pytest.approx(revolved(area, cx), rel=1e-4)


def test_a_round_too_large_names_the_step_and_the_field_and_builds_nothing():
    base = Protocol(BASE, (KNOB,))
    before = build(base)
    with pytest.raises(OperationError, match=r"step 2 \(bevel\).*radius = 16 mm"):
        replay(base.append(rim(3.0, radius=16.0)))
    assert build(base).Volume() == before.Volume()


def test_a_hole_mouth_is_rounded_from_the_face_around_it():
    hole = Sweep(
        FaceRef((0.0, 0.0, 5.0), (0.0, 0.0, 1.0)),
        (0.0, 0.0, 5.0),
        8.0,
        8.0,
        6.0,
        ((8.0, 2.0), (8.0, 4.0)),
        Mode.SUBTRACT,
    )
    c = (0.0, 8.0, 5.0)  # the mouth's far side, off the circle's seam
    op = Bevel(
        FaceRef((20.0, 20.0, 5.0), (0.0, 0.0, 1.0)),
        c,
        None,
        quarter(c, (0, 1, 0), (0, 0, -1), 2.0),
        radius=2.0,
    )
    p = Protocol(BASE, (hole,))
    removed = build(p).Volume() - build(p.append(op)).Volume()
    area = 4 * (1 - math.pi / 4)
    centroid = 8 + 2 * (10 - 3 * math.pi) / (12 - 3 * math.pi)
    assert removed == pytest.approx(revolved(area, centroid), rel=1e-6)


def test_the_outline_rounds_every_edge_of_the_face():
    drawn = build(Protocol(BASE, (top_edge(radius=2.0),)))
    outline = build(Protocol(BASE, (top_edge(radius=2.0, edges=EdgeSet.OUTLINE),)))
    kinds = [f.geomType() for f in outline.Faces()]
    assert [f.geomType() for f in drawn.Faces()].count("CYLINDER") == 1
    assert kinds.count("CYLINDER") == 4  # the four top edges, and a blend at each corner
    assert outline.Volume() < drawn.Volume()


def test_the_crease_form_fillets_its_crease():
    solid = build(rounded_box())
    assert solid.Volume() == pytest.approx(60 * 60 * 10 - 4 * 25 * (1 - math.pi / 4) * 10, rel=1e-9)


def test_a_tangent_chain_runs_round_the_rounded_outline():
    p = rounded_box()
    solid = build(p)
    top = [
        e for e in solid.Edges() if abs(e.Center().z - 5.0) < 1e-9 and abs(e.Center().y + 30) < 1e-9
    ]
    chain = tangent_chain(solid, edge_faces(solid), top[0])
    assert len(chain) == 8
    chained = build(p.append(top_edge(radius=2.0, edges=EdgeSet.CHAIN)))
    assert chained.isValid() and chained.Volume() < solid.Volume()


def test_a_freeform_profile_along_several_edges_is_refused():
    with pytest.raises(OperationError, match="freeform profile l follows one straight edge"):
        build(rounded_box().append(top_edge(edges=EdgeSet.CHAIN)))


def test_a_freeform_profile_on_a_concave_rim_adds_material():
    c = (R, 0.0, 5.0)  # where the knob stands on the box
    op = Bevel(
        FaceRef((25.0, 25.0, 5.0), (0.0, 0.0, 1.0)),
        c,
        None,
        quarter(c, (1, 0, 0), (0, 0, 1), 3.0),
    )
    assert knob_with(op).Volume() > knob_volume()


def test_a_profile_off_the_edge_s_normal_plane_is_refused():
    op = rim(3.0)
    tilted = (op.profile[0], op.profile[1], op.profile[2], (R, 4.0, TOP - 3.0))
    with pytest.raises(OperationError, match="off the plane normal to the edge"):
        knob_with(Bevel(DISK, op.corner, None, tilted))


def test_a_point_inside_f_is_no_edge():
    op = rim(3.0)
    with pytest.raises(OperationError, match="lies inside face f"):
        knob_with(Bevel(DISK, (5.0, 0.0, TOP), None, op.profile, radius=3.0))


def test_a_failed_round_leaves_its_input_solid_as_it_was():
    solid = make_box(BASE)
    with pytest.raises(OperationError, match="cannot fillet 1 edge"):
        apply_operation(solid, top_edge(radius=40.0))
    assert solid.Volume() == 60 * 60 * 10 and len(solid.Faces()) == 6


def test_a_rim_on_a_cone_is_rounded_too():
    cone = Sweep(
        FaceRef((0.0, 0.0, 5.0), (0.0, 0.0, 1.0)),
        (0.0, 0.0, 5.0),
        15.0,
        10.0,
        20.0,
        ((40 / 3, 20 / 3), (35 / 3, 40 / 3)),
        Mode.ADD,
    )
    # across the top rim (radius 10) at (10, 0, 25): into the disk, and down the cone's side
    down = np.array([5.0, 0.0, -20.0]) / np.hypot(5.0, 20.0)
    c = (10.0, 0.0, TOP)
    op = Bevel(DISK, c, None, quarter(c, (-1, 0, 0), down, 2.0), radius=2.0)
    p = Protocol(BASE, (cone,))
    rounded = build(p.append(op))
    assert rounded.isValid() and 0 < build(p).Volume() - rounded.Volume() < 2 * math.pi * 10 * 4
