# SPDX-License-Identifier: LGPL-2.1-or-later
"""Turning projected curves into freehand-looking strokes (paper, "Sketch rendering").

Each stroke's end points move by Gaussian noise; the displacement is spread smoothly
along the stroke, a little low-frequency wobble is added, and the result is lightly
smoothed. Noise levels follow the paper's robustness study: an end point moves by 1.4%,
2.8% or 4.1% of the image diagonal (root mean square of the 2D displacement) for levels
1, 2 and 3, i.e. a Gaussian of that size divided by sqrt(2) along each axis.
"""
from __future__ import annotations

import numpy as np

NOISE_FRACTION = {1: 0.014, 2: 0.028, 3: 0.041}


def densify(points: np.ndarray, step: float = 2.0) -> np.ndarray:
    """A polyline resampled about every `step` pixels (at least its end points)."""
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    n = max(int(np.ceil(s[-1] / step)) + 1, 2)
    t = np.linspace(0, s[-1], n)
    return np.stack([np.interp(t, s, points[:, k]) for k in range(points.shape[1])], axis=1)


def _smooth(p: np.ndarray, closed: bool, passes: int = 2) -> np.ndarray:
    for _ in range(passes):
        if closed:
            p = (np.roll(p, 1, axis=0) + 2 * p + np.roll(p, -1, axis=0)) / 4
        elif len(p) > 2:
            p[1:-1] = (p[:-2] + 2 * p[1:-1] + p[2:]) / 4
    return p


def perturb(points: np.ndarray, rng: np.random.Generator, sigma: float,
            closed: bool = False) -> np.ndarray:
    """A freehand version of a projected curve (K, 2), noise `sigma` pixels."""
    p = densify(np.asarray(points, float))
    t = np.linspace(0.0, 1.0, len(p))[:, None]
    if closed:
        # A closed curve has no end points: a smooth periodic displacement instead.
        k = np.arange(1, 3)[None, :]
        ph = rng.uniform(0, 2 * np.pi, (2, 2))
        amp = rng.normal(0, sigma / 2, (2, 2))
        ang = 2 * np.pi * t * k
        disp = np.stack([(amp[0] * np.cos(ang + ph[0])).sum(1),
                         (amp[1] * np.cos(ang + ph[1])).sum(1)], axis=1)
        disp += rng.normal(0, sigma / 3, 2)
    else:
        a, b = rng.normal(0, sigma, (2, 2))
        disp = (1 - t) * a + t * b
        freq = rng.uniform(0.5, 1.5)
        normal = p[-1] - p[0]
        normal = np.array([-normal[1], normal[0]]) / max(np.linalg.norm(normal), 1e-9)
        disp += normal * (0.15 * sigma * rng.normal()) * np.sin(np.pi * freq * t)
    return _smooth(p + disp, closed)


def noise_sigma(level: int, width: int, height: int) -> float:
    """The per-axis endpoint noise (pixels) of a noise level for an image size."""
    if level not in NOISE_FRACTION:
        raise ValueError(f"noise level must be 1, 2 or 3, got {level}")
    return NOISE_FRACTION[level] * float(np.hypot(width, height)) / np.sqrt(2.0)
