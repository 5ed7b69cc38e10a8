# SPDX-License-Identifier: LGPL-2.1-or-later
"""Strokes on a curved face are back-projected onto the surface (view rays meet the
cylinder, not a plane), so a prism or sweep sketched on a cylinder's side is recovered,
and the side's edges moved along its normals are read as its radius changed:
synthetic strokes from the sketch generator's curves, with their labels, fitted back."""

import numpy as np
import pytest

from Sketch2CADWorkbench.brep.faces import resolve_face
from Sketch2CADWorkbench.brep.operators import apply_operation, make_box
from Sketch2CADWorkbench.brep.protocol import (
    AddSubPrism,
    Box,
    Extrude,
    FaceRef,
    Mode,
    Surface,
    Sweep,
)
from Sketch2CADWorkbench.inference.fitting.addsub import fit_prism
from Sketch2CADWorkbench.inference.fitting.common import FitError
from Sketch2CADWorkbench.inference.fitting.extrude import fit_extrude
from Sketch2CADWorkbench.inference.fitting.surface import surface_hits
from Sketch2CADWorkbench.inference.fitting.sweep import fit_sweep, sweep_fit
from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.sketch.curves import operation_curves
from Sketch2CADWorkbench.sketch.labels import EXTRUDE_OFFSET, EXTRUDE_PROFILE

R = 12.0  # a post of radius R standing on a box, its axis along z from z=5 to z=65
CYL = Surface.CYLINDER
SIDE = FaceRef((0.0, -R, 35.0), (0.0, -1.0, 0.0), CYL)  # the post's front, facing -y


def straight(r0, r1, d):
    return ((r0 + (r1 - r0) / 3, d / 3), (r0 + 2 * (r1 - r0) / 3, 2 * d / 3))


@pytest.fixture(scope="module")
def post():
    box = make_box(Box((40.0, 40.0, 10.0)))
    top = FaceRef((0.0, 0.0, 5.0), (0.0, 0.0, 1.0))
    return apply_operation(box, Sweep(top, (0.0, 0.0, 5.0), R, R, 60.0, straight(R, R, 60)))


@pytest.fixture(scope="module")
def view():
    """From the front, a little to the left and above: the post's front is in view."""
    d = np.array([0.45, 1.0, -0.45])
    return OrthoCamera((0.0, 0.0, 35.0), tuple(d / np.linalg.norm(d)), (0.0, 0.0, 1.0), 40.0)


def sketch(solid, op, camera):
    """The generator's curves of `op` projected into the view: strokes and labels."""
    curves = operation_curves(solid, op, camera.direction)
    return [camera.project(c.points)[0] for c in curves], [c.label for c in curves]


def side_face(solid):
    return resolve_face(solid, SIDE).face


def test_view_rays_meet_the_cylinder_where_it_faces_the_viewer(post, view):
    on_side = np.array([[0.0, -R, 35.0], [R * np.sin(0.5), -R * np.cos(0.5), 20.0]])
    hits = surface_hits(view, view.project(on_side)[0], side_face(post))
    assert hits == pytest.approx(on_side, abs=1e-6)  # the front, not the back of the post
    miss = surface_hits(view, view.project(np.array([[30.0, -30.0, 35.0]]))[0], side_face(post))
    assert np.isnan(miss).all()


def test_a_ray_the_hand_drew_just_past_the_cylinders_outline_meets_it_there(post, view):
    # the post's outline at mid-height, on the right: where its normal is across the view
    theta = np.arctan2(-view.direction[0], view.direction[1])
    normal = np.array([np.cos(theta), np.sin(theta), 0.0])
    edge = R * normal + (0.0, 0.0, 35.0)
    outward = view.image_of(normal) / np.linalg.norm(view.image_of(normal))
    pixel = view.project(edge[None])[0][0]
    near, far = surface_hits(
        view, np.array([pixel + 2.0 * outward, pixel + 20 * outward]), side_face(post)
    )
    assert near == pytest.approx(edge, abs=0.05)  # a hand's 2 px: the outline point
    assert np.isnan(far).all()  # 20 px beside the post: in the air


def test_a_boss_drawn_flush_with_the_posts_top_a_pixel_past_its_rim_is_read(post, view):
    top = 65.0
    poly = ((-4.0, -R, top - 8), (4.0, -R, top - 8), (4.0, -R, top), (-4.0, -R, top))
    truth = AddSubPrism(FaceRef((0.0, -R, top - 4), SIDE.normal, CYL), poly, 5.0, Mode.ADD)
    strokes, labels = sketch(post, truth, view)
    up = view.image_of(np.array([0.0, 0.0, 1.0]))
    drawn = [s + up / np.linalg.norm(up) for s in strokes]  # the hand, a pixel high
    op = fit_prism(post, side_face(post), view, drawn, labels)
    assert op.mode is Mode.ADD and op.d == pytest.approx(5.0, abs=0.3)
    assert np.array(op.polygon)[:, 2].max() == pytest.approx(top, abs=0.8)
    want = apply_operation(post, truth).Volume() - post.Volume()
    assert apply_operation(post, op).Volume() - post.Volume() == pytest.approx(want, rel=0.15)


@pytest.mark.parametrize("mode, d", [(Mode.ADD, 5.0), (Mode.SUBTRACT, 3.0)])
def test_a_prism_sketched_on_a_cylinders_side_is_recovered(post, view, mode, d):
    poly = ((-5.0, -R, 30.0), (5.0, -R, 31.0), (4.0, -R, 41.0), (-4.0, -R, 40.0))
    # p_f, where the prism stands, is under the mean of its corners
    truth = AddSubPrism(FaceRef((0.0, -R, 35.5), SIDE.normal, CYL), poly, d, mode)
    strokes, labels = sketch(post, truth, view)
    op = fit_prism(post, side_face(post), view, strokes, labels, option=mode)
    assert op.face.surface is CYL and op.mode is mode
    assert op.face.point == pytest.approx(truth.face.point, abs=0.1)
    assert op.face.normal == pytest.approx(SIDE.normal, abs=0.01)
    assert op.d == pytest.approx(d, abs=0.3)
    got = np.array(op.polygon)
    assert max(np.min(np.linalg.norm(got - v, axis=1)) for v in poly) < 0.4
    # the recovered step builds and removes or adds nearly what the true one does
    want = apply_operation(post, truth).Volume() - post.Volume()
    assert apply_operation(post, op).Volume() - post.Volume() == pytest.approx(want, rel=0.08)


def test_an_addition_on_the_side_is_read_as_one_without_being_told(post, view):
    poly = ((-5.0, -R, 30.0), (5.0, -R, 30.0), (5.0, -R, 40.0), (-5.0, -R, 40.0))
    strokes, labels = sketch(post, AddSubPrism(SIDE, poly, 6.0), view)
    op = fit_prism(post, side_face(post), view, strokes, labels)
    assert op.mode is Mode.ADD and op.d == pytest.approx(6.0, abs=0.3)


def test_a_radial_peg_sketched_on_a_cylinders_side_is_recovered(post, view):
    truth = Sweep(SIDE, SIDE.point, 4.0, 4.0, 10.0, straight(4, 4, 10))
    strokes, labels = sketch(post, truth, view)
    op = fit_sweep(post, side_face(post), view, strokes, labels, option=Mode.ADD)
    assert op.face.surface is CYL
    assert np.array(op.center) == pytest.approx(SIDE.point, abs=0.5)
    assert (op.r0, op.r1, op.d) == pytest.approx((4.0, 4.0, 10.0), abs=0.5)


def test_a_radial_peg_read_with_a_bulge_has_a_straight_reading_too(post, view):
    # pipe session step 4: a peg's straight sides read as a profile bulging 3 mm out; the
    # caller scores the straight reading beside it
    truth = Sweep(SIDE, SIDE.point, 4.0, 3.0, 10.0, ((6.5, 3.0), (6.0, 7.0)))
    strokes, labels = sketch(post, truth, view)
    got = sweep_fit(post, side_face(post), view, strokes, labels, option=Mode.ADD)
    assert not got.straight and got.refined() == got.operation
    line = got.refined(straight=True)
    fitted = got.operation
    assert (line.center, line.r0, line.r1, line.d) == (
        fitted.center,
        fitted.r0,
        fitted.r1,
        fitted.d,
    )
    assert np.array(line.profile) == pytest.approx(np.array(straight(line.r0, line.r1, line.d)))
    assert apply_operation(post, line).isValid()


def test_a_peg_drawn_wider_than_the_post_is_refused_saying_why(post, view):
    truth = Sweep(SIDE, SIDE.point, 4.0, 4.0, 10.0, straight(4, 4, 10))
    strokes, labels = sketch(post, truth, view)
    c = view.project(np.array([SIDE.point]))[0][0]
    wide = [c + 3.3 * (s - c) for s in strokes]  # a base circle of radius ~13 on T: R is 12
    with pytest.raises(FitError, match="reaches past the side of the curved face"):
        fit_sweep(post, side_face(post), view, wide, labels, option=Mode.ADD)


def test_an_outline_off_the_curved_face_is_refused(post, view):
    poly = ((-5.0, -R, 30.0), (5.0, -R, 30.0), (5.0, -R, 40.0), (-5.0, -R, 40.0))
    strokes, labels = sketch(post, AddSubPrism(SIDE, poly, 6.0), view)
    far_off = [s + (400.0, 0.0) for s in strokes]  # drawn in the air beside the post
    with pytest.raises(FitError):
        fit_prism(post, side_face(post), view, far_off, labels)


@pytest.mark.parametrize("d", [3.0, -4.0])
def test_a_cylinders_side_extruded_is_read_as_its_radius_changed(post, view, d):
    truth = Extrude(SIDE, d)
    strokes, labels = sketch(post, truth, view)
    offset = [s for s, label in zip(strokes, labels, strict=False) if label == EXTRUDE_OFFSET]
    sides = [s for s, label in zip(strokes, labels, strict=False) if label == EXTRUDE_PROFILE]
    op = fit_extrude(post, side_face(post), view, offset, sides)
    assert op.d == pytest.approx(d, abs=0.2)
    # named on the side, where it faces the viewer, and replayed as the same step
    assert op.face.surface is CYL
    assert np.asarray(op.face.normal) @ view.direction < -0.9
    assert apply_operation(post, op).Volume() == pytest.approx(
        apply_operation(post, truth).Volume(), rel=0.02
    )


def test_a_cylinder_is_never_read_as_shrunk_to_its_axis(post, view):
    strokes, _labels = sketch(post, Extrude(SIDE, -1.1 * R), view)  # drawn past its axis
    shrunk = fit_extrude(post, side_face(post), view, strokes)
    assert -R < shrunk.d < 0
    apply_operation(post, shrunk)  # builds
