# SPDX-License-Identifier: LGPL-2.1-or-later
"""A shell's rim: which strokes draw it, and the wall thickness it says."""

import numpy as np
import pytest

from Sketch2CADWorkbench.brep.faces import face_ref_of
from Sketch2CADWorkbench.brep.geometry import polyline_length
from Sketch2CADWorkbench.brep.operators import apply_operation, make_box
from Sketch2CADWorkbench.brep.protocol import AddSubPrism, Box, FaceRef, Mode, OperationError, Shell
from Sketch2CADWorkbench.inference.fitting.common import FitError
from Sketch2CADWorkbench.inference.fitting.shell import (
    rim_and_wall,
    shell_fit,
    thickest_that_builds,
)
from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.sketch.curves import rim_wires

BOX = make_box(Box((60.0, 40.0, 30.0)))
TOP = next(f for f in BOX.Faces() if f.normalAt().z > 0.9)
CAMERA = OrthoCamera((0.0, 0.0, 0.0), (0.4, 0.5, -0.77), (0.0, 0.0, 1.0), 50.0)


def sides(points3d: np.ndarray, wobble: float = 0.0, seed: int = 0) -> list[np.ndarray]:
    """One stroke (pixels) per side of a closed 3D polygon, each end moved by `wobble` px."""
    rng = np.random.default_rng(seed)
    px = CAMERA.project(points3d)[0]
    out = []
    for a, b in zip(px, np.roll(px, -1, axis=0), strict=True):
        a, b = a + rng.normal(0, wobble, 2), b + rng.normal(0, wobble, 2)
        out.append(np.linspace(a, b, 20))
    return out


def rim_corners(t: float) -> np.ndarray:
    (wire,) = rim_wires(TOP, t)
    return np.array([e.startPoint().toTuple() for e in wire.Edges()])


def test_the_rim_is_the_closed_strokes_and_a_wall_line_is_set_aside():
    rim = sides(rim_corners(3.0))
    corner = rim[0][0]
    wall = np.linspace(corner, corner + [0.0, 40.0], 15)
    drawn = rim_and_wall([rim[0], wall, *rim[1:]])
    assert drawn.rim == (0, 2, 3, 4) and drawn.wall == 1
    assert rim_and_wall(rim).wall is None


@pytest.mark.parametrize("short", [0.1, 0.15])
def test_a_rim_whose_corners_gape_as_a_sloppy_hand_leaves_them_is_a_rim(short):
    # each side stops short of its corner by `short` of its length: gaps that grow with
    # the rim, not with the sketch around it
    rim = [s[: int(len(s) * (1 - short))] for s in sides(rim_corners(3.0))]
    assert rim_and_wall(rim).rim == (0, 1, 2, 3)


def test_a_rim_with_one_corner_left_wide_open_is_a_rim():
    # the two sides at one corner each stop short by 30% of their length, as a level-3
    # hand leaves a corner: the gap is over half the sides, its two ends still each
    # other's nearest
    rim = sides(rim_corners(3.0))
    rim[0] = rim[0][: int(0.7 * len(rim[0]))]
    rim[1] = rim[1][int(0.3 * len(rim[1])) :]
    gap = np.linalg.norm(rim[0][-1] - rim[1][0])
    assert gap > 0.5 * min(polyline_length(rim[0]), polyline_length(rim[1]))
    assert rim_and_wall(rim).rim == (0, 1, 2, 3)


def test_a_prism_with_its_depth_lines_is_no_rim():
    base = rim_corners(3.0)
    far = base - [0.0, 0.0, 12.0]
    px = CAMERA.project(np.vstack([base, far]))[0]
    depth = [np.linspace(px[i], px[i + 4], 10) for i in range(4)]
    with pytest.raises(FitError, match="do not close into one rim"):
        rim_and_wall(sides(base) + depth)
    with pytest.raises(FitError, match="do not close into one rim"):
        rim_and_wall(sides(base) + depth + sides(far))


@pytest.mark.parametrize("t, wobble", [(3.0, 0.0), (3.0, 1.0), (6.0, 2.0)])
def test_t_is_where_the_rim_lies_inside_the_outline(t, wobble):
    op = shell_fit(BOX, TOP, CAMERA, sides(rim_corners(t), wobble, seed=int(t)))
    assert op.face == face_ref_of(TOP)
    # exact strokes: t to a hundredth of a pixel (the fit compares points of the outline)
    assert op.t == pytest.approx(t, abs=(3 * wobble + 0.01) * CAMERA.pixel_size)


def test_an_outline_that_is_no_inset_is_refused_saying_how_far_off():
    square = np.array([[-25, -15, 15], [-5, -15, 15], [-5, 5, 15], [-25, 5, 15]], float)
    with pytest.raises(FitError, match="no rim of the face"):
        shell_fit(BOX, TOP, CAMERA, sides(square))


def test_the_rim_of_a_face_with_a_boss_on_it_is_drawn_around_its_hole():
    boss = AddSubPrism(
        FaceRef((0.0, 0.0, 15.0), (0.0, 0.0, 1.0)),
        ((-5, -5, 15), (5, -5, 15), (5, 5, 15), (-5, 5, 15)),
        5.0,
        Mode.SUBTRACT,
    )
    holed = apply_operation(BOX, boss)
    top = next(f for f in holed.Faces() if f.normalAt().z > 0.9 and f.Center().z > 14)
    assert len(rim_wires(top, 2.0)) == 2  # the outline inset, the hole grown


@pytest.mark.parametrize("t", [2.0, 8.5])  # 8.5: the rim a small circle near the middle
def test_t_is_read_from_a_circular_rim_drawn_as_one_loop(t):
    import cadquery as cq

    drum = cq.Workplane().circle(10.0).extrude(5.0).val()
    top = next(f for f in drum.Faces() if f.geomType() == "PLANE" and f.Center().z > 4)
    (wire,) = rim_wires(top, t)
    ring = np.array([wire.positionAt(u).toTuple() for u in np.linspace(0.3, 1.3, 90) % 1])
    op = shell_fit(drum, top, CAMERA, [CAMERA.project(ring)[0]])
    assert op.t == pytest.approx(t, abs=0.05 * CAMERA.pixel_size)


def test_a_rim_read_past_what_the_solid_takes_is_the_thickest_wall_that_builds():
    # the 40 mm wide box opened at the top holds a cavity while t < 20 mm
    rim_read = Shell(face_ref_of(TOP), 22.0)
    with pytest.raises(OperationError):
        apply_operation(BOX, rim_read, TOP)
    got = thickest_that_builds(BOX, TOP, rim_read)
    assert 20.0 - 22.0 / 32 < got.t < 20.0, got.t  # within two of the halvings' steps
    apply_operation(BOX, got, TOP)  # builds
    fits = Shell(face_ref_of(TOP), 3.0)
    assert thickest_that_builds(BOX, TOP, fits) == fits


def test_a_wall_no_thinner_t_builds_keeps_its_reason():
    with pytest.raises(OperationError, match="more than the solid allows"):
        thickest_that_builds(BOX, TOP, Shell(face_ref_of(TOP), 50.0))


def test_a_thin_walls_rim_spilling_past_one_side_is_read_and_one_leaving_the_face_refused():
    # a 1 mm wall: the rim's long side drawn 0.3 mm past the face's edge (a third of the
    # rim's samples outside the face) is still read, t below a millimetre
    c = rim_corners(1.0)
    spilled = c + [[0.0, 1.3, 0.0], [0.0, 1.3, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]
    assert 0.3 < shell_fit(BOX, TOP, CAMERA, sides(spilled)).t < 1.0
    # two sides past the edges: half of it leaves the face
    off = spilled + [[0.0, 0.0, 0.0], [1.3, 0.0, 0.0], [1.3, 0.0, 0.0], [0.0, 0.0, 0.0]]
    with pytest.raises(FitError, match="leaves the face to open"):
        shell_fit(BOX, TOP, CAMERA, sides(off))
