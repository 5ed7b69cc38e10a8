# SPDX-License-Identifier: LGPL-2.1-or-later
"""Which 3D points a camera sees, given the depth of the rendered solid."""
from __future__ import annotations

import numpy as np
from scipy import ndimage

from .camera import OrthoCamera
from .maps import ContextMaps


def visible(points: np.ndarray, camera: OrthoCamera, maps: ContextMaps, tol: float) -> np.ndarray:
    """Per point: inside the image and not behind the rendered surface.

    A point counts as visible when its view depth is at most the deepest surface
    depth in its 3x3 pixel neighbourhood plus `tol` (mm), so points on silhouettes
    and crease edges, which share pixels with farther surfaces, are seen.
    """
    px, depth = camera.project(points)
    i, j = np.floor(px[:, 0]).astype(int), np.floor(px[:, 1]).astype(int)
    inside = (i >= 0) & (i < camera.width) & (j >= 0) & (j < camera.height)
    deepest = ndimage.maximum_filter(maps.view_depth, size=3, mode="nearest")
    out = np.zeros(len(px), bool)
    out[inside] = depth[inside] <= deepest[j[inside], i[inside]] + tol
    return out


def visible_fraction(points: np.ndarray, camera: OrthoCamera, maps: ContextMaps,
                     tol: float) -> float:
    """The share of the points that `visible` accepts."""
    return float(visible(points, camera, maps, tol).mean()) if len(points) else 0.0
