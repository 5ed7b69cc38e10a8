# SPDX-License-Identifier: LGPL-2.1-or-later
"""Freehand strokes: the paper's noise levels, smooth perturbation, and their maps."""

import numpy as np
import pytest

from datagen.strokes import NOISE_FRACTION, noise_sigma, perturb, sketch_strokes, stroke_maps
from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.sketch.curves import Curve

LINE = np.array([[20.0, 30.0], [220.0, 90.0]])
DIAGONAL = np.hypot(256, 256)


@pytest.mark.parametrize("level", [1, 2, 3])
def test_noise_levels_move_end_points_by_the_papers_share_of_the_diagonal(level):
    rng = np.random.default_rng(level)
    sigma = noise_sigma(level, 256, 256)
    moved = np.array(
        [[perturb(LINE, rng, sigma)[k] - LINE[k] for k in (0, -1)] for _ in range(400)]
    ).reshape(-1, 2)
    rms = np.sqrt(np.mean(np.sum(moved**2, axis=1)))
    assert rms == pytest.approx(NOISE_FRACTION[level] * DIAGONAL, rel=0.1)


def test_the_displacement_varies_smoothly_along_a_stroke():
    rng = np.random.default_rng(5)
    stroke = perturb(LINE, rng, noise_sigma(3, 256, 256))
    steps = np.linalg.norm(np.diff(stroke, axis=0), axis=1)
    assert steps.max() < 3.0  # no jumps: ~2 px spacing, gently stretched
    bend = np.diff(stroke, 2, axis=0)
    assert np.abs(bend).max() < 0.5  # no kinks


def test_a_closed_curve_becomes_a_loop_whose_ends_need_not_meet():
    t = np.linspace(0, 2 * np.pi, 96, endpoint=False)
    circle = 128 + 40 * np.stack([np.cos(t), np.sin(t)], axis=1)
    rng = np.random.default_rng(6)
    gaps, radii = [], []
    for _ in range(50):
        s = perturb(circle, rng, noise_sigma(1, 256, 256), closed=True)
        gaps.append(np.linalg.norm(s[0] - s[-1]))
        radii.append(np.linalg.norm(s - 128, axis=1))
    assert np.median(gaps) > 1.0
    assert np.median(np.abs(np.concatenate(radii) - 40)) < 6.0


def test_strokes_follow_their_curves_and_carry_their_labels():
    camera = OrthoCamera((0.0, 0.0, 0.0), (0.0, 0.0, -1.0), (0.0, 1.0, 0.0), 50.0)
    curves = [
        Curve(np.array([[-30.0, -30, 0], [30, -30, 0]]), 1),
        Curve(np.array([[-30.0, 30, 0], [30, 30, 0]]), 0),
        Curve(np.array([[0.0, -20, 0], [0, 20, 0]]), 2),
    ]
    strokes, labels = sketch_strokes(curves, camera, np.random.default_rng(7), 1)
    assert sorted(labels) == [0, 1, 2]
    for s, label in zip(strokes, labels, strict=False):
        exact = camera.project(curves[[c.label for c in curves].index(label)].points)[0]
        assert np.linalg.norm(s[[0, -1]] - exact, axis=1).max() < 25.0
    maps = stroke_maps(strokes, labels, 256, 256)
    on = maps.stroke_mask > 0
    assert np.array_equal(maps.sketch, maps.stroke_mask)
    assert np.all(maps.curve_label[~on] == 0)
    assert set(np.unique(maps.curve_label[on])) == {0.0, 1.0, 2.0}


def test_unknown_noise_levels_are_refused():
    with pytest.raises(ValueError, match="noise level"):
        noise_sigma(4, 256, 256)
