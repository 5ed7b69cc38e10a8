# SPDX-License-Identifier: LGPL-2.1-or-later
"""Which 3D points a camera sees, given the view depth of the rendered solid."""

from __future__ import annotations

import numpy as np

from .camera import OrthoCamera
from .maps import ContextMaps

# The 3x3 pixel neighbourhood: its centres surround any point of the middle pixel.
_OFFSETS = np.array([(di, dj) for dj in (-1, 0, 1) for di in (-1, 0, 1)])


def visible(points: np.ndarray, camera: OrthoCamera, maps: ContextMaps, tol: float) -> np.ndarray:
    """Per point: inside the image and not hidden behind the rendered surface.

    A point is visible when its view depth is at most the deepest surface depth among
    the 3x3 pixels around it plus `tol`. The depth map is sampled at pixel centres;
    those nine centres surround the point, so the deepest of them on a plane through
    the point is at least as deep as the point: points on sloped faces, creases and
    silhouettes (where the neighbourhood also sees the background, +inf) count as seen.

    Args:
        points: (N, 3) world points (mm).
        camera: the camera `maps` were rendered with.
        maps: the rendered maps (view_depth is used).
        tol: depth slack in mm; it must cover the tessellation's chordal deviation
            (e.g. 1e-3 of the model's size, or a couple of pixel sizes).
    Returns:
        (N,) bool.
    """
    px, depth = camera.project(np.asarray(points, float).reshape(-1, 3))
    i, j = np.floor(px[:, 0]).astype(int), np.floor(px[:, 1]).astype(int)
    h, w = maps.view_depth.shape
    inside = (i >= 0) & (i < w) & (j >= 0) & (j < h)
    ni = np.clip(i[inside, None] + _OFFSETS[:, 0], 0, w - 1)
    nj = np.clip(j[inside, None] + _OFFSETS[:, 1], 0, h - 1)
    deepest = maps.view_depth[nj, ni].max(axis=1)
    out = np.zeros(len(px), bool)
    out[inside] = depth[inside] <= deepest + tol
    return out


def visible_fraction(
    points: np.ndarray, camera: OrthoCamera, maps: ContextMaps, tol: float
) -> float:
    """The share of `points` that `visible` accepts (0 for no points).

    Args:
        points: (N, 3) world points (mm).
        camera: the camera `maps` were rendered with.
        maps: the rendered maps.
        tol: depth slack in mm, as for `visible`.
    Returns:
        A fraction in [0, 1].
    """
    return float(visible(points, camera, maps, tol).mean()) if len(points) else 0.0
