# SPDX-License-Identifier: LGPL-2.1-or-later
"""Choosing cameras: the paper's context frustum around a sketch, and framing a shape."""
from __future__ import annotations

import numpy as np

from .camera import OrthoCamera

MIN_EXTENT_PX = 8.0  # a dot-like sketch still gets a sensible context window


def context_camera(view: OrthoCamera, stroke_pixels: np.ndarray, factor: float = 2.0,
                   size: int = 256) -> OrthoCamera:
    """The context view: a square `factor` times the sketch's bounding box, centred on it.

    Args:
        view: the camera the strokes were drawn in.
        stroke_pixels: (N, 2) all stroke points, in `view`'s pixels.
        factor: frustum size relative to the bounding box (2 in the paper).
        size: the context maps' width and height in pixels.
    """
    p = np.asarray(stroke_pixels, float)
    lo, hi = p.min(axis=0), p.max(axis=0)
    extent = max(float((hi - lo).max()), MIN_EXTENT_PX)
    centre = view.unproject(((lo + hi) / 2)[None], 0.0)[0]
    scale = 0.5 * extent * view.pixel_size * factor
    return OrthoCamera(tuple(map(float, centre)), view.direction, view.up, scale, size, size)


def fit_camera(bbox_min, bbox_max, direction, up, margin: float = 1.1,
               width: int = 256, height: int = 256) -> OrthoCamera:
    """A view along `direction` framing the box [bbox_min, bbox_max] with some margin."""
    lo, hi = np.asarray(bbox_min, float), np.asarray(bbox_max, float)
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                        for z in (lo[2], hi[2])])
    centre = (lo + hi) / 2
    probe = OrthoCamera(tuple(centre), tuple(direction), tuple(up), 1.0, width, height)
    r, u, _ = probe.basis()
    rel = corners - centre
    half_w, half_h = np.abs(rel @ r).max(), np.abs(rel @ u).max()
    scale = margin * max(half_h, half_w * height / width, 1e-9)
    return OrthoCamera(tuple(map(float, centre)), tuple(direction), tuple(up), float(scale),
                       width, height)
