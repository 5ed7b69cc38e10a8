# SPDX-License-Identifier: LGPL-2.1-or-later
"""Bevel, prism and sweep fitting recover the operation that produced the strokes."""
import numpy as np
import pytest
from fit_sketches import circle3d, curve_stroke, face_towards, polygon_strokes, stroke

from Sketch2CADWorkbench.brep.geometry import bezier
from Sketch2CADWorkbench.brep.operators import apply_operation
from Sketch2CADWorkbench.brep.protocol import Mode
from Sketch2CADWorkbench.inference.fitting.addsub import fit_prism
from Sketch2CADWorkbench.inference.fitting.bevel import fit_bevel
from Sketch2CADWorkbench.inference.fitting.common import FitError
from Sketch2CADWorkbench.inference.fitting.primitive import other_option_fits
from Sketch2CADWorkbench.inference.fitting.regularize import regularize_operation
from Sketch2CADWorkbench.inference.fitting.sweep import fit_sweep

FRONT_Y = -15.0
TOP_Z = 10.0


# ----------------------------------------------------------------- bevel

def bevel_profile():
    """A rounded profile at the front face's top-left corner (-20, -15, 10)."""
    return np.array([[-14.0, FRONT_Y, TOP_Z], [-17.5, FRONT_Y, TOP_Z], [-20, FRONT_Y, 7.5],
                     [-20, FRONT_Y, 4.0]])


def test_bevel_fit_finds_the_corner_its_crease_and_the_profile(box, camera):
    ctrl = bevel_profile()
    face = face_towards(box, (0, -1, 0))
    op = fit_bevel(box, face, camera, curve_stroke(camera, bezier(ctrl, np.linspace(0, 1, 40))))
    assert op.corner == pytest.approx((-20, FRONT_Y, TOP_Z))
    assert op.opposite == pytest.approx((-20, -FRONT_Y, TOP_Z))
    assert np.array(op.profile) == pytest.approx(ctrl, abs=0.3)
    assert apply_operation(box, op).isValid()


def test_bevel_stroke_drawn_backwards_gives_the_same_corner(box, camera):
    ctrl = bevel_profile()[::-1]
    op = fit_bevel(box, face_towards(box, (0, -1, 0)), camera,
                   curve_stroke(camera, bezier(ctrl, np.linspace(0, 1, 40))))
    assert op.corner == pytest.approx((-20, FRONT_Y, TOP_Z))


def test_bevel_profile_inside_the_face_is_refused(box, camera):
    inner = np.array([[-5, FRONT_Y, 0], [-2, FRONT_Y, 3], [2, FRONT_Y, 3], [5, FRONT_Y, 0]])
    with pytest.raises(FitError, match="from one edge of the face to another"):
        fit_bevel(box, face_towards(box, (0, -1, 0)), camera,
                  curve_stroke(camera, bezier(inner, np.linspace(0, 1, 30))))


# ----------------------------------------------------------------- prism

def regularized(solid, op, camera):
    """The fitted operation as regularization leaves it (rectified and snapped in `camera`)."""
    return regularize_operation(solid, op, face_towards(solid, op.face.normal), camera).operation


def prism_sketch(camera, base, height, sign, noise=0.0, rng=None):
    top = base + np.array([0, 0, sign * height])
    start, end = (base, top) if sign > 0 else (top, base)
    strokes = polygon_strokes(camera, start, noise, rng) + polygon_strokes(camera, end, noise, rng)
    labels = [0] * len(start) + [2] * len(end)
    for a, b in zip(start, end):
        strokes.append(stroke(camera, a, b, noise=noise, rng=rng))
        labels.append(1)
    return strokes, labels


QUAD = np.array([[-9, -6, TOP_Z], [7, -7, TOP_Z], [8, 4, TOP_Z], [-8, 6, TOP_Z]])


def test_prism_fit_recovers_an_addition_exactly(box, camera):
    strokes, labels = prism_sketch(camera, QUAD, 6.0, +1)
    op = fit_prism(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)
    assert op.mode is Mode.ADD and op.d == pytest.approx(6.0, abs=0.2)
    got = np.array(op.polygon)
    for v in QUAD:  # same vertex set, any starting vertex
        assert np.min(np.linalg.norm(got - v, axis=1)) < 0.2


def test_a_start_outline_drawn_off_is_corrected_by_the_far_outline_and_side_edges(box, camera):
    # the start outline drawn 4 px to the right, the other eight strokes where they belong:
    # the base polygon follows the majority, not the four strokes that sit on f
    strokes, labels = prism_sketch(camera, QUAD, 6.0, +1)
    strokes = [s + (4.0, 0.0) if l == 0 else s for s, l in zip(strokes, labels)]
    op = fit_prism(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)
    got = np.array(op.polygon)
    err = max(np.min(np.linalg.norm(got - v, axis=1)) for v in QUAD)
    # from the start outline alone the corners would be 4 px off
    assert err < 0.5 * 4.0 * camera.pixel_size and op.d == pytest.approx(6.0, abs=0.3)


def test_deep_cut_is_read_as_a_subtraction(box, camera):
    strokes, labels = prism_sketch(camera, QUAD, 14.0, -1)
    op = fit_prism(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)
    assert op.mode is Mode.SUBTRACT and op.d == pytest.approx(14.0, abs=0.2)


def test_a_low_boss_whose_top_also_lies_on_f_names_the_hole_that_draws_the_same(box, camera):
    # seen along the view, the 6 mm boss's top outline falls inside the top face: a hole
    # with that rim, 6 mm deep, draws the same nine lines (paper, Fig. 5b)
    from Sketch2CADWorkbench.inference.fitting.verify import reprojection_error
    face = face_towards(box, (0, 0, 1))
    strokes, labels = prism_sketch(camera, QUAD, 6.0, +1)
    boss = fit_prism(box, face, camera, strokes, labels)
    assert boss.mode is Mode.ADD and other_option_fits(face, camera, boss, 1e-6)
    hole = fit_prism(box, face, camera, strokes, labels, option=Mode.SUBTRACT)
    assert hole.d == pytest.approx(6.0, abs=0.2)
    assert reprojection_error(box, hole, camera, strokes) < 1.0


def test_a_tall_boss_whose_top_leaves_f_names_no_other_option(box, camera):
    face = face_towards(box, (0, 0, 1))
    strokes, labels = prism_sketch(camera, QUAD, 25.0, +1)
    boss = fit_prism(box, face, camera, strokes, labels)
    assert boss.mode is Mode.ADD and not other_option_fits(face, camera, boss, 1e-6)


def test_a_plate_wider_than_the_column_top_it_stands_on_is_an_addition_on_it(box, camera):
    # a 10 x 10 column on the box, then a 30 x 24 plate on the column's top: no sample of
    # either plate outline lies on that face, but the plate's region covers all of it
    from Sketch2CADWorkbench.brep.protocol import AddSubPrism, FaceRef
    column = AddSubPrism(FaceRef((0.0, 0.0, TOP_Z), (0.0, 0.0, 1.0)),
                         ((-5, -5, TOP_Z), (5, -5, TOP_Z), (5, 5, TOP_Z), (-5, 5, TOP_Z)),
                         8.0, Mode.ADD)
    solid = apply_operation(box, column)
    z = TOP_Z + 8.0
    top = next(f for f in solid.Faces() if f.normalAt().z > 0.999 and f.Center().z > z - 1e-6)
    plate = np.array([[-15, -12, z], [15, -12, z], [15, 12, z], [-15, 12, z]])
    strokes, labels = prism_sketch(camera, plate, 5.0, +1)
    op = fit_prism(solid, top, camera, strokes, labels)
    assert op.mode is Mode.ADD and op.d == pytest.approx(5.0, abs=0.3)
    got = np.array(op.polygon)
    assert max(np.min(np.linalg.norm(got - v, axis=1)) for v in plate) < 0.5


def test_user_choice_of_option_wins(box, camera):
    strokes, labels = prism_sketch(camera, QUAD, 6.0, +1)
    op = fit_prism(box, face_towards(box, (0, 0, 1)), camera, strokes, labels,
                   option=Mode.SUBTRACT)
    assert op.mode is Mode.SUBTRACT


def test_noisy_near_rectangle_is_regularized_to_an_exact_rectangle(box, camera):
    rng = np.random.default_rng(1)
    rect = np.array([[-8.7, -4.6, TOP_Z], [9.2, -5.3, TOP_Z], [9.5, 5.1, TOP_Z], [-9.1, 5.4, TOP_Z]])
    strokes, labels = prism_sketch(camera, rect, 5.0, +1, noise=0.7, rng=rng)
    op = regularized(box, fit_prism(box, face_towards(box, (0, 0, 1)), camera, strokes, labels),
                     camera)
    p = np.array(op.polygon)[:, :2]
    sides = np.roll(p, -1, axis=0) - p
    # right angles and sides parallel to the box edges (x and y), centre snapped to the face centre
    assert all(abs(sides[i] @ sides[(i + 1) % 4]) < 1e-6 for i in range(4))
    assert all(min(abs(s[0]), abs(s[1])) < 1e-6 for s in sides)
    assert p.mean(axis=0) == pytest.approx((0, 0), abs=1e-9)


def test_hexagon_is_regularized_to_a_regular_hexagon(box, camera):
    ang = np.radians([0, 62, 118, 181, 238, 301])
    rad = np.array([5.0, 5.4, 4.8, 5.2, 4.9, 5.1])
    hexa = np.stack([rad * np.cos(ang) + 6, rad * np.sin(ang) + 2, np.full(6, TOP_Z)], axis=1)
    strokes, labels = prism_sketch(camera, hexa, 4.0, +1)
    op = regularized(box, fit_prism(box, face_towards(box, (0, 0, 1)), camera, strokes, labels),
                     camera)
    p = np.array(op.polygon)[:, :2]
    sides = np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1)
    assert sides == pytest.approx(np.full(6, sides.mean()), rel=1e-9)
    radii = np.linalg.norm(p - p.mean(axis=0), axis=1)
    assert radii == pytest.approx(np.full(6, radii.mean()), rel=1e-9)


@pytest.mark.parametrize("count", [2, 7])
def test_prism_needs_three_to_six_profile_strokes(box, camera, count):
    strokes, labels = prism_sketch(camera, QUAD, 6.0, +1)
    profiles = [s for s, l in zip(strokes, labels) if l == 1]
    strokes = [s for s, l in zip(strokes, labels) if l != 1] + (profiles * 2)[:count]
    labels = [l for l in labels if l != 1] + [1] * count
    with pytest.raises(FitError, match=f"3 to 6 profile strokes.*{count} were recognised"):
        fit_prism(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)


def test_outlines_off_the_face_are_refused(box, camera):
    far = QUAD + np.array([60.0, 0, 0])
    strokes, labels = prism_sketch(camera, far, 6.0, +1)
    with pytest.raises(FitError, match="neither the start nor the end outline"):
        fit_prism(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)


# ----------------------------------------------------------------- sweep

def sweep_sketch(camera, c0, r0, r1, height, sign, rh_profile=None):
    """Circles at both ends and the two silhouettes (in the plane facing the camera)."""
    c0 = np.asarray(c0, float)
    c1 = c0 + np.array([0, 0, sign * height])
    start, end = (circle3d(c0, r0), circle3d(c1, r1)) if sign > 0 else \
        (circle3d(c1, r1), circle3d(c0, r0))
    strokes = [curve_stroke(camera, start), curve_stroke(camera, end)]
    labels = [0, 2]
    f = np.array(camera.direction)
    side = np.cross([0, 0, 1.0], f)
    side /= np.linalg.norm(side)
    for s in (1, -1):
        if rh_profile is None:
            pts = np.linspace(c0 + s * r0 * side, c1 + s * r1 * side, 30)
        else:
            rh = bezier(np.array(rh_profile), np.linspace(0, 1, 40))
            pts = c0 + s * rh[:, :1] * side + sign * rh[:, 1:2] * np.array([0, 0, 1.0])
        strokes.append(curve_stroke(camera, pts))
        labels.append(1)
    return strokes, labels


def test_sweep_fit_recovers_a_cone(box, camera):
    strokes, labels = sweep_sketch(camera, (4, -2, TOP_Z), 6.0, 3.0, 10.0, +1)
    op = fit_sweep(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)
    assert op.mode is Mode.ADD
    assert op.center == pytest.approx((4, -2, TOP_Z), abs=0.15)
    assert (op.r0, op.r1, op.d) == pytest.approx((6.0, 3.0, 10.0), abs=0.2)


def test_sweep_fit_recovers_a_curved_profile(box, camera):
    prof = [(5.0, 0.0), (9.0, 3.0), (2.0, 7.0), (4.0, 10.0)]
    strokes, labels = sweep_sketch(camera, (2, 0, TOP_Z), 5.0, 4.0, 10.0, +1, prof)
    op = fit_sweep(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)
    assert np.array(op.profile) == pytest.approx(np.array(prof[1:3]), abs=0.6)


def test_a_profile_stroke_that_swings_far_outside_the_circles_is_not_taken_as_drawn(box, camera):
    strokes, labels = sweep_sketch(camera, (2, 0, TOP_Z), 5.0, 4.0, 10.0, +1)
    wild = [(5.0, 0.0), (40.0, -30.0), (-20.0, 45.0), (4.0, 10.0)]  # r, h far out
    swinging, _ = sweep_sketch(camera, (2, 0, TOP_Z), 5.0, 4.0, 10.0, +1, wild)
    strokes[2:] = swinging[2:]  # the circles as drawn, the profiles swinging out
    op = fit_sweep(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)
    (r1, h1), (r2, h2) = op.profile
    assert 0 <= h1 <= h2 <= 10.0 + 1e-6 and 0 < max(r1, r2) <= 10.0


def test_nearly_straight_equal_radii_become_an_exact_cylinder(box, camera):
    strokes, labels = sweep_sketch(camera, (3.3, 2.2, TOP_Z), 5.0, 5.4, 8.0, +1)
    op = regularized(box, fit_sweep(box, face_towards(box, (0, 0, 1)), camera, strokes, labels),
                     camera)
    assert op.r0 == op.r1
    assert np.array(op.profile) == pytest.approx(np.array([(op.r0, op.d / 3), (op.r0, 2 * op.d / 3)]))


def test_deep_hole_is_read_as_a_subtraction(box, camera):
    strokes, labels = sweep_sketch(camera, (0, 0, TOP_Z), 4.0, 4.0, 16.0, -1)
    op = fit_sweep(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)
    assert op.mode is Mode.SUBTRACT and op.d == pytest.approx(16.0, abs=0.3)


def test_sweep_without_its_far_circle_is_refused(box, camera):
    strokes, labels = sweep_sketch(camera, (0, 0, TOP_Z), 4.0, 4.0, 8.0, +1)
    with pytest.raises(FitError, match="both circle outlines"):
        fit_sweep(box, face_towards(box, (0, 0, 1)), camera, strokes[:1] + strokes[2:],
                  labels[:1] + labels[2:])
