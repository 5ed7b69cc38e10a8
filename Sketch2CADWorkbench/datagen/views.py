# SPDX-License-Identifier: LGPL-2.1-or-later
"""Informative views of a sketched operation (paper, "Sketch rendering").

A view looks at the base face from 20 to 80 degrees off its normal, with world z (or y
for near-vertical views) upwards; its frustum is centred on the sketch curves and
scaled by a random 1.6 to 2.4 times their extent.
"""
from __future__ import annotations

import numpy as np

from ..render.camera import OrthoCamera

ANGLE_RANGE_DEG = (20.0, 80.0)
SCALE_RANGE = (1.6, 2.4)
MAX_OCCLUSION = 0.2


def view_direction(rng: np.random.Generator, normal: np.ndarray) -> np.ndarray:
    """A unit view direction (into the scene) at 20-80 degrees from looking straight at f."""
    n = np.asarray(normal, float)
    a = np.cross(n, [1.0, 0, 0] if abs(n[0]) < 0.9 else [0, 1.0, 0])
    a /= np.linalg.norm(a)
    b = np.cross(n, a)
    phi = rng.uniform(0, 2 * np.pi)
    theta = np.radians(rng.uniform(*ANGLE_RANGE_DEG))
    w = np.cos(phi) * a + np.sin(phi) * b
    return -(np.cos(theta) * n + np.sin(theta) * w)


def up_vector(direction: np.ndarray) -> tuple[float, float, float]:
    """World z, unless the view looks almost straight up or down."""
    return (0.0, 0.0, 1.0) if abs(direction[2]) < 0.95 else (0.0, 1.0, 0.0)


def frame_curves(points: np.ndarray, direction: np.ndarray, factor: float,
                 size: int = 256) -> OrthoCamera:
    """A square view along `direction` centred on the points, `factor` times their extent."""
    d = np.asarray(direction, float)
    probe = OrthoCamera((0.0, 0.0, 0.0), tuple(d), up_vector(d), 1.0, size, size)
    r, u, _ = probe.basis()
    x, y = points @ r, points @ u
    centre = r * (x.min() + x.max()) / 2 + u * (y.min() + y.max()) / 2
    centre += d * float(np.mean(points @ d))
    extent = max(x.max() - x.min(), y.max() - y.min(), 1e-6)
    return OrthoCamera(tuple(map(float, centre)), tuple(map(float, d)), up_vector(d),
                       float(0.5 * extent * factor), size, size)
