# SPDX-License-Identifier: LGPL-2.1-or-later
"""Rasterising 2D strokes (pixel polylines) into maps."""
from __future__ import annotations

import cv2
import numpy as np

_SHIFT = 4  # OpenCV fixed-point bits: strokes keep 1/16-pixel precision


def _cv_points(polyline: np.ndarray) -> np.ndarray:
    # Our pixel (i, j) spans [i, i+1); OpenCV puts pixel i's centre at integer i.
    p = (np.asarray(polyline, float) - 0.5) * (1 << _SHIFT)
    return np.round(p).astype(np.int32).reshape(-1, 1, 2)


def rasterize(polylines: list[np.ndarray], width: int, height: int,
              values: list[float] | None = None, thickness: int = 1) -> np.ndarray:
    """Draw polylines into an (H, W) float32 map, 8-connected, without anti-aliasing.

    Args:
        polylines: (K, 2) pixel positions each (x right, y down).
        width, height: the map size.
        values: the value drawn for each polyline (default 1.0); later ones overwrite.
        thickness: line width in pixels.
    """
    out = np.zeros((height, width), np.float32)
    if values is None:
        values = [1.0] * len(polylines)
    for line, value in zip(polylines, values):
        if len(line) < 2:
            continue
        mask = np.zeros((height, width), np.uint8)
        cv2.polylines(mask, [_cv_points(line)], False, 1, thickness, cv2.LINE_8, _SHIFT)
        out[mask > 0] = value
    return out
