# SPDX-License-Identifier: LGPL-2.1-or-later
"""Extrude fitting recovers d from the moved face's outline."""

import contextlib

import numpy as np
import pytest
from fit_sketches import edge_strokes, face_towards, stroke

from Sketch2CADWorkbench.brep.faces import model_scale
from Sketch2CADWorkbench.inference.fitting.common import FitError
from Sketch2CADWorkbench.inference.fitting.extrude import fit_extrude, fit_extrude_by_ends
from Sketch2CADWorkbench.render.camera import OrthoCamera


@pytest.mark.parametrize(
    "normal,d", [((0, 0, 1), 7.3), ((0, 0, 1), -6.1), ((0, -1, 0), 11.0), ((-1, 0, 0), -4.4)]
)
def test_exact_strokes_give_d_within_a_search_step(box, camera, normal, d):
    face = face_towards(box, normal)
    op = fit_extrude(box, face, camera, edge_strokes(camera, face, d * np.array(normal, float)))
    assert op.d == pytest.approx(d, abs=0.0075 * model_scale(box))
    assert op.face.normal == pytest.approx(normal)


def test_noisy_strokes_give_d_within_two_pixels(box, camera):
    rng = np.random.default_rng(3)
    face = face_towards(box, (0, 0, 1))
    strokes = [s + rng.normal(0, 1.0, s.shape) for s in edge_strokes(camera, face, (0, 0, 9.0))]
    op = fit_extrude(box, face, camera, strokes)
    assert op.d == pytest.approx(9.0, abs=2 * camera.pixel_size)


def test_head_on_view_is_refused(box):
    face = face_towards(box, (0, 0, 1))
    top_down = OrthoCamera((0, 0, 0), (0, 0, -1), (0, 1, 0), 30.0)
    with pytest.raises(FitError, match="head-on"):
        fit_extrude(box, face, top_down, edge_strokes(top_down, face, (0, 0, 5.0)))


def test_strokes_far_from_any_offset_are_refused(box, camera):
    face = face_towards(box, (0, 0, 1))
    far = [np.array([[2.0, 2.0], [6.0, 3.0]])]  # a scribble in the image corner
    with pytest.raises(FitError, match="no offset of the face matches"):
        fit_extrude(box, face, camera, far)


def test_a_face_far_larger_than_the_context_is_sampled_within_the_cap(box, camera, monkeypatch):
    # a context a hundredth of a millimetre per pixel: one sample per pixel along the
    # top's 140 mm of edges would be 14,000 samples times every candidate offset
    from Sketch2CADWorkbench.inference.fitting import extrude

    fine = OrthoCamera(camera.center, camera.direction, camera.up, 1.28, 256, 256)
    face = face_towards(box, (0, 0, 1))
    seen = []
    search = extrude.line_search
    monkeypatch.setattr(
        extrude,
        "line_search",
        lambda points, *a, **k: seen.append(len(points)) or search(points, *a, **k),
    )
    # a sketch in the middle of the frame: the face's edges run far out of it; only the
    # samples matter here
    with contextlib.suppress(FitError):
        fit_extrude(box, face, fine, [np.array([[100.0, 128.0], [156.0, 128.0]])])
    assert seen and seen[0] <= extrude.MAX_EDGE_SAMPLES + 2 * len(face.Edges())


def _hand_drawn(box, camera, d, rng, sigma):
    """The top's extrusion by d as the hand datagen/strokes.py models draws it: each end
    of a stroke off by Gaussian noise (`sigma` px per axis), spread linearly along it;
    the four moved edges, then the four side edges."""
    face = face_towards(box, (0, 0, 1))
    corners = np.array([v.toTuple() for v in face.Vertices()])
    edges = [
        (np.array(e.startPoint().toTuple()), np.array(e.endPoint().toTuple())) for e in face.Edges()
    ]
    up = np.array([0.0, 0.0, d])
    segments = [(a + up, b + up) for a, b in edges] + [(c, c + up) for c in corners]
    strokes = []
    for a, b in segments:
        t = np.linspace(0.0, 1.0, 30)[:, None]
        line = camera.project(a + t * (b - a))[0]
        strokes.append(line + (1 - t) * rng.normal(0, sigma, 2) + t * rng.normal(0, sigma, 2))
    return face, strokes


def test_a_hand_drawn_extrusion_is_read_closer_with_the_strokes_ends(box, camera):
    # the level-1 hand: 3.6 px on 256
    rng = np.random.default_rng(0)
    misses = {0.0: [], 1.0: []}
    for _ in range(120):
        d = rng.uniform(4.0, 12.0)
        face, strokes = _hand_drawn(box, camera, d, rng, 3.6)
        for weight, got in misses.items():
            op = fit_extrude(box, face, camera, strokes[:4], strokes[4:], end_weight=weight)
            got.append(abs(op.d - d))
    # d off by 0.47 mm on average by closeness alone, 0.37 with the ends (1 px: 0.25 mm;
    # with another seed 0.41 and 0.35)
    assert np.mean(misses[1.0]) < 0.9 * np.mean(misses[0.0])


def test_a_round_faces_extrusion_is_read_by_closeness_alone(camera, monkeypatch):
    # a disk's outline is one loop and its sides are silhouettes: no stroke ends at its
    # seam vertex, so the strokes' ends say nothing about d there
    import cadquery as cq

    from Sketch2CADWorkbench.inference.fitting import extrude

    disk = cq.Solid.makeCylinder(12.0, 10.0)
    face = face_towards(disk, (0, 0, 1))
    seen = []
    search = extrude.line_search
    monkeypatch.setattr(
        extrude, "line_search", lambda *a, **k: seen.append(a[6]) or search(*a, **k)
    )
    rim = [
        np.array(face.Edges()[0].positionAt(t).toTuple()) + (0, 0, 5.0)
        for t in np.linspace(0, 1, 40)
    ]
    sides = [stroke(camera, (12.0, 0.0, 10.0), (12.0, 0.0, 15.0))]
    op = fit_extrude(disk, face, camera, [camera.project(np.array(rim))[0]], sides)
    assert seen == [None]
    assert op.d == pytest.approx(5.0, abs=0.5)


def test_exact_strokes_give_d_exactly_by_their_ends(box, camera):
    face = face_towards(box, (0, 0, 1))
    corners = [np.array(v.toTuple()) for v in face.Vertices()]
    sides = [stroke(camera, c, c + (0, 0, 7.3)) for c in corners]
    op = fit_extrude_by_ends(box, face, camera, edge_strokes(camera, face, (0, 0, 7.3)), sides)
    assert op.d == pytest.approx(7.3, abs=1e-6)
    assert op.face.normal == pytest.approx((0, 0, 1))


def test_a_rough_hand_is_read_closer_by_the_strokes_ends_than_by_the_line_search(box, camera):
    # the level-3 hand (10.5 px on 256): the line search matches the moved outline to the
    # strokes' pixels, which follow each end's miss (mean miss 0.79 against 1.1 mm;
    # seeds 1-3 the same within 0.02)
    rng = np.random.default_rng(1)
    by_ends, by_search = [], []
    for _ in range(60):
        d = rng.uniform(4.0, 12.0)
        face, strokes = _hand_drawn(box, camera, d, rng, 10.5)
        by_ends.append(abs(fit_extrude_by_ends(box, face, camera, strokes[:4], strokes[4:]).d - d))
        by_search.append(abs(fit_extrude(box, face, camera, strokes[:4], strokes[4:]).d - d))
    assert np.mean(by_ends) < 0.9 * np.mean(by_search)


def test_a_stroke_far_from_every_line_does_not_move_d(box, camera):
    face = face_towards(box, (0, 0, 1))
    corners = [np.array(v.toTuple()) for v in face.Vertices()]
    sides = [stroke(camera, c, c + (0, 0, 6.0)) for c in corners]
    outline = edge_strokes(camera, face, (0, 0, 6.0))
    stray = stroke(camera, (40.0, 40.0, 60.0), (60.0, 40.0, 60.0))
    op = fit_extrude_by_ends(box, face, camera, outline + [stray], sides)
    assert op.d == pytest.approx(6.0, abs=1e-6)


def test_a_round_face_is_left_to_the_line_search(camera):
    import cadquery as cq

    disk = cq.Solid.makeCylinder(12.0, 10.0)
    face = face_towards(disk, (0, 0, 1))
    rim = [
        np.array(face.Edges()[0].positionAt(t).toTuple()) + (0, 0, 5.0)
        for t in np.linspace(0, 1, 40)
    ]
    assert fit_extrude_by_ends(disk, face, camera, [camera.project(np.array(rim))[0]], []) is None


def _tube_side():
    import cadquery as cq

    tube = cq.Solid.makeCylinder(11.0, 60.0)
    return tube, next(f for f in tube.Faces() if f.geomType() == "CYLINDER")


@pytest.mark.parametrize("d", [1.0, -2.5])
def test_a_tubes_radial_offset_is_read_from_its_rims_and_the_ends_of_its_lines(camera, d):
    # the pipe session's step 2: its rims are loops, read by closeness; the seam and the
    # side edges at its corners by their ends
    from Sketch2CADWorkbench.brep.protocol import Extrude
    from Sketch2CADWorkbench.inference.fitting.extrude import _facing_ref
    from Sketch2CADWorkbench.sketch.curves import operation_curves

    tube, side = _tube_side()
    truth = Extrude(_facing_ref(side, camera), d)
    curves = operation_curves(tube, truth, camera.direction)
    strokes = [camera.project(c.points)[0] for c in curves]
    rims = [s for s in strokes if np.allclose(s[0], s[-1])]
    lines = [s for s in strokes if not np.allclose(s[0], s[-1])]
    assert len(rims) == 2  # drawn as loops, back to their start
    op = fit_extrude_by_ends(tube, side, camera, rims, lines)
    assert op.d == pytest.approx(d, abs=0.02)
    assert op.face.surface is not None  # named on the side, where it faces us
    assert fit_extrude_by_ends(tube, side, camera, [], []) is None
