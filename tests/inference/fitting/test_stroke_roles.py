# SPDX-License-Identifier: LGPL-2.1-or-later
"""Stroke roles read from geometry: the fallback when the curve map mixes up the strokes."""

import numpy as np
import pytest

from Sketch2CADWorkbench.brep.faces import FaceFrame, resolve_face
from Sketch2CADWorkbench.brep.operators import make_box
from Sketch2CADWorkbench.brep.protocol import AddSubPrism, Box, FaceRef, Mode, Sweep
from Sketch2CADWorkbench.inference.fitting import stroke_roles as stroke_roles_module
from Sketch2CADWorkbench.inference.fitting.common import FitError
from Sketch2CADWorkbench.inference.fitting.stroke_roles import normal_image, stroke_roles
from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.sketch.curves import operation_curves

TOP = FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0))
BOX = Box((40, 30, 20))


def camera(direction):
    d = np.asarray(direction, float)
    return OrthoCamera((0.0, 0.0, 5.0), tuple(d / np.linalg.norm(d)), (0, 0, 1), 45.0, 800, 600)


def roles_and_truth(op, direction):
    solid = make_box(BOX)
    cam = camera(direction)
    curves = operation_curves(solid, op, np.array(cam.direction))
    strokes = [cam.project(c.points)[0] for c in curves]
    frame = FaceFrame.of(resolve_face(solid, TOP).face)
    return (
        stroke_roles(strokes, frame, cam, prism=isinstance(op, AddSubPrism)),
        [c.label for c in curves],
    )


@pytest.mark.parametrize("mode", [Mode.ADD, Mode.SUBTRACT])
@pytest.mark.parametrize("direction", [(-1, 1, -1), (0.6, 0.9, -1.2)])
def test_prism_strokes_get_start_profile_and_end_roles(mode, direction):
    # in the second view the triangle's side from (-3, 8) to (-10, -5) runs almost
    # along the image of the normal, like the side edges do
    op = AddSubPrism(TOP, ((-10, -5, 10), (4, -5, 10), (-3, 8, 10)), 6.0, mode)
    got, truth = roles_and_truth(op, direction)
    assert got == truth


@pytest.mark.parametrize("r1", [6.0, 9.0])
def test_sweep_circles_and_profile_lines_get_their_roles(r1):
    op = Sweep(TOP, (0.0, 0.0, 10.0), 6.0, r1, 10.0, ((6.0, 10 / 3), (r1, 20 / 3)), Mode.ADD)
    got, truth = roles_and_truth(op, (0.6, 0.9, -1.2))
    assert got == truth


def test_a_face_seen_head_on_has_no_readable_profile():
    op = AddSubPrism(TOP, ((-10, -5, 10), (4, -5, 10), (-3, 8, 10)), 6.0, Mode.ADD)
    with pytest.raises(FitError, match="head-on"):
        roles_and_truth(op, (0.01, 0.0, -1.0))


def test_a_strongly_flared_cone_is_read_from_its_two_closed_circles():
    # profile silhouettes at about 70 degrees from the axis: none runs along n_f's image
    op = Sweep(TOP, (0.0, 0.0, 10.0), 5.0, 16.0, 4.0, ((8.7, 4 / 3), (12.3, 8 / 3)), Mode.ADD)
    got, truth = roles_and_truth(op, (0.6, 0.9, -1.2))
    assert got == truth


def test_a_side_edge_drawn_short_still_counts_without_the_chord_test():
    # a freehand side edge stopping halfway: its chord no longer matches the others'
    op = AddSubPrism(TOP, ((-10, -5, 10), (4, -5, 10), (4, 6, 10), (-10, 6, 10)), 8.0, Mode.ADD)
    solid = make_box(BOX)
    cam = camera((-1, 1, -1))
    curves = operation_curves(solid, op, np.array(cam.direction))
    strokes = [cam.project(c.points)[0] for c in curves]
    side = next(k for k, c in enumerate(curves) if c.label == 1)
    a, b = strokes[side][0], strokes[side][-1]
    strokes[side] = np.array([a, (a + b) / 2])
    frame = FaceFrame.of(resolve_face(solid, TOP).face)
    truth = [c.label for c in curves]
    assert stroke_roles(strokes, frame, cam, prism=True).count(1) < 4
    assert stroke_roles(strokes, frame, cam, prism=True, same_chord=None) == truth


def test_a_short_side_edge_leaning_from_stroke_noise_is_still_a_profile():
    op = AddSubPrism(TOP, ((-10, -5, 10), (4, -5, 10), (-3, 8, 10)), 2.0, Mode.SUBTRACT)
    solid = make_box(BOX)
    cam = camera((-1, 1, -1))
    curves = operation_curves(solid, op, np.array(cam.direction))
    strokes = [cam.project(c.points)[0] for c in curves]
    n2 = normal_image(cam, FaceFrame.of(resolve_face(solid, TOP).face))
    side = next(k for k, c in enumerate(curves) if c.label == 1)
    a, b = strokes[side][0], strokes[side][-1]
    assert np.linalg.norm(b - a) < 25  # a short edge: 5 px is 12+ degrees
    strokes[side] = np.array([a, b + 5.0 * np.array([-n2[1], n2[0]])])
    frame = FaceFrame.of(resolve_face(solid, TOP).face)
    assert stroke_roles(strokes, frame, cam, prism=True, same_chord=None) == [
        c.label for c in curves
    ]


def test_the_work_grows_linearly_with_the_strokes(monkeypatch):
    # thousands of short strokes (a stress test, not a sketch): a third along n_f's
    # image, a tenth closed loops; the points queried in the k-d trees must grow about
    # as the strokes do (summing every profile end per closed loop grew quadratically)
    queried = []

    class Counting(stroke_roles_module.cKDTree):
        def query(self, x, *args, **kwargs):
            queried.append(np.asarray(x).size // 2)
            return super().query(x, *args, **kwargs)

    monkeypatch.setattr(stroke_roles_module, "cKDTree", Counting)
    solid = make_box(BOX)
    cam = camera((0.6, 0.9, -1.2))
    frame = FaceFrame.of(resolve_face(solid, TOP).face)
    n2 = normal_image(cam, frame)
    work = []
    for n in (1000, 2000):
        rng = np.random.default_rng(5)
        strokes = []
        for k in range(n):
            start = rng.uniform((50, 50), (750, 550))
            if k % 3 == 0:
                strokes.append(start + np.linspace(0, 1, 6)[:, None] * rng.uniform(10, 40) * n2)
            elif k % 10 == 1:
                a = np.linspace(0, 2 * np.pi, 12)
                strokes.append(start + rng.uniform(5, 15) * np.stack([np.cos(a), np.sin(a)], 1))
            else:
                strokes.append(start + np.cumsum(rng.normal(0, 4.0, (5, 2)), 0))
        queried.clear()
        roles = stroke_roles(strokes, frame, cam, prism=False)
        assert roles.count(1) > stroke_roles_module.NEAR_PROFILES
        work.append(sum(queried))
    assert work[1] < 2.5 * work[0]


def test_a_slot_seen_nearly_along_its_length_has_its_depth_edges_as_the_second_reading():
    # its long sides run along n_f's image too, and match one another as the side edges
    # do: the largest set of alike chords may be either; the other is the second reading
    op = AddSubPrism(TOP, ((-7, -1, 10), (7, -1, 10), (7, 1, 10), (-7, 1, 10)), 3.0, Mode.SUBTRACT)
    solid = make_box(BOX)
    cam = camera((-0.51, 0.02, -0.86))
    curves = operation_curves(solid, op, np.array(cam.direction))
    strokes = [cam.project(c.points)[0] for c in curves]
    frame = FaceFrame.of(resolve_face(solid, TOP).face)
    truth = [c.label for c in curves]
    readings = [stroke_roles(strokes, frame, cam, prism=True, group=g) for g in (0, 1)]
    assert truth in readings
    other = readings[1 - readings.index(truth)]
    long_sides = [k for k, c in enumerate(curves) if c.label != 1 and np.ptp(c.points[:, 0]) > 10]
    assert sorted(k for k, r in enumerate(other) if r == 1) == long_sides
    with pytest.raises(FitError, match="no set 3"):
        stroke_roles(strokes, frame, cam, prism=True, group=2)


def test_a_hole_drawn_without_its_hidden_lines_has_its_whole_rim_as_the_end_outline():
    from Sketch2CADWorkbench.inference.fitting.stroke_roles import whole_outline_roles

    solid = make_box(Box((40.0, 30.0, 20.0)))
    cam = OrthoCamera((0.0, 0.0, 0.0), (0.4, 0.6, -0.7), (0.0, 0.0, 1.0), 48.0, 256, 256)
    rim = np.array([[-8, -6, 10], [8, -6, 10], [8, 6, 10], [-8, 6, 10]], float)
    floor = rim - (0, 0, 6.0)
    px = lambda p: cam.project(np.asarray(p, float))[0]  # noqa: E731
    sides = [px(np.linspace(rim[i], rim[(i + 1) % 4], 12)) for i in range(4)]
    depth = px(np.linspace(rim[2], floor[2], 12))  # the far corner's side edge
    piece = px(np.linspace(floor[2], floor[3], 12)[:6])  # part of the floor
    strokes = [depth, *sides[::-1], piece]
    frame = FaceFrame.of(resolve_face(solid, FaceRef((0, 0, 10), (0, 0, 1))).face)
    assert whole_outline_roles(strokes, frame, cam, 10.0) == [1, 2, 2, 2, 2, 0]
