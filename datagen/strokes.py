# SPDX-License-Identifier: LGPL-2.1-or-later
"""Freehand strokes from projected sketch curves, and their maps (paper, "Sketch rendering").

Each curve is projected to pixels and becomes one stroke. Its two end points move by
Gaussian noise and the displacement is spread smoothly along the stroke (linearly in
arc length), a little low-frequency wobble is added across the stroke, and the result
is lightly smoothed. A closed curve (a circle) starts at a random point of the loop
and is perturbed the same way, so its ends no longer meet exactly, plus a smooth
periodic distortion of its shape.

Noise levels follow the paper's robustness study: the root mean square of an end
point's 2D displacement is 1.4%, 2.8% or 4.1% of the image diagonal for levels 1, 2
and 3 (5.1, 10.1 and 14.8 pixels on 256 x 256), i.e. a Gaussian of that size divided
by sqrt(2) along each axis. Level 1 is the paper's training setting.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from Sketch2CADWorkbench.brep.geometry import arc_lengths, resample_every
from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.render.strokes import rasterize
from Sketch2CADWorkbench.sketch.curves import Curve

NOISE_FRACTION = {1: 0.014, 2: 0.028, 3: 0.041}
STEP_PX = 2.0  # spacing of a stroke's points
WOBBLE = 0.15  # wobble amplitude across the stroke, in endpoint sigmas
LOOP_DISTORTION = 0.35  # amplitude of a loop's periodic distortion, in endpoint sigmas


@dataclass
class StrokeMaps:
    """Rasterised strokes, (H, W) float32 in the camera's pixel convention.

    Attributes:
        sketch: S, 1 on stroke pixels, 0 elsewhere.
        stroke_mask: M~, the same pixels (kept apart: the loss masks with it).
        curve_label: C~, each stroke pixel's curve label (0 off the strokes); where
            strokes cross, the one drawn later wins.
    """

    sketch: np.ndarray
    stroke_mask: np.ndarray
    curve_label: np.ndarray


def noise_sigma(level: int, width: int, height: int) -> float:
    """The per-axis endpoint noise (pixels) of a noise level for an image size."""
    if level not in NOISE_FRACTION:
        raise ValueError(f"noise level must be 1, 2 or 3, got {level}")
    return NOISE_FRACTION[level] * float(np.hypot(width, height)) / np.sqrt(2.0)


def _smooth(p: np.ndarray, passes: int = 2) -> np.ndarray:
    """[1 2 1]/4 smoothing with the end points held."""
    p = p.copy()
    for _ in range(passes):
        if len(p) > 2:
            p[1:-1] = (p[:-2] + 2 * p[1:-1] + p[2:]) / 4
    return p


def perturb(
    points: np.ndarray, rng: np.random.Generator, sigma: float, closed: bool = False
) -> np.ndarray:
    """A freehand version (K', 2) of a projected curve (K, 2), endpoint noise `sigma` px.

    Args:
        points: the exact curve in pixels; for a closed curve the loop without its
            repeated first point.
        rng: the random generator.
        sigma: per-axis standard deviation of the end points' displacement (pixels).
        closed: the curve is a loop.
    """
    p = np.asarray(points, float)
    if closed:
        p = np.roll(p, -int(rng.integers(len(p))), axis=0)
        p = np.concatenate([p, p[:1]])
    p = resample_every(p, STEP_PX)
    s = arc_lengths(p)
    t = (s / max(s[-1], 1e-9))[:, None]
    a, b = rng.normal(0, sigma, (2, 2))
    disp = (1 - t) * a + t * b
    if closed:
        # A hand-drawn ellipse is a little lopsided: low harmonics of the loop parameter.
        k = np.array([2.0, 3.0])
        amp = rng.normal(0, LOOP_DISTORTION * sigma / np.sqrt(2), (2, 2))
        phase = rng.uniform(0, 2 * np.pi, (2, 2))
        ang = 2 * np.pi * t * k[None]
        disp += np.stack(
            [(amp[0] * np.cos(ang + phase[0])).sum(1), (amp[1] * np.cos(ang + phase[1])).sum(1)],
            axis=1,
        )
    else:
        chord = p[-1] - p[0]
        across = np.array([-chord[1], chord[0]]) / max(np.linalg.norm(chord), 1e-9)
        freq = rng.uniform(0.5, 1.5)
        disp += across * (WOBBLE * sigma * rng.normal()) * np.sin(np.pi * freq * t)
    return _smooth(p + disp)


def sketch_strokes(
    curves: list[Curve], camera: OrthoCamera, rng: np.random.Generator, noise_level: int
) -> tuple[list[np.ndarray], list[int]]:
    """Freehand strokes (pixels) of the curves seen by `camera`, with their labels, in a
    random drawing order (designers draw in any order; it decides which label wins
    where strokes cross)."""
    sigma = noise_sigma(noise_level, camera.width, camera.height)
    pixels = camera.project(np.concatenate([c.points for c in curves]))[0]
    ends = np.cumsum([len(c.points) for c in curves])[:-1]
    strokes = [
        perturb(p, rng, sigma, c.closed)
        for p, c in zip(np.split(pixels, ends), curves, strict=False)
    ]
    order = rng.permutation(len(strokes))
    return [strokes[i] for i in order], [int(curves[i].label) for i in order]


def stroke_maps(
    strokes: list[np.ndarray], labels: list[int], width: int, height: int
) -> StrokeMaps:
    """S, M~ and C~ of the strokes (1-pixel, 8-connected lines)."""
    sketch = rasterize(strokes, width, height)
    return StrokeMaps(
        sketch, sketch.copy(), rasterize(strokes, width, height, [float(v) for v in labels])
    )
