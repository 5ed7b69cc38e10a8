# SPDX-License-Identifier: LGPL-2.1-or-later
"""Rasterising 2D strokes (pixel polylines) into maps, 8-connected, without anti-aliasing."""

from __future__ import annotations

import cv2
import numpy as np

_SHIFT = 4  # OpenCV fixed-point bits: strokes keep 1/16-pixel precision


def _cv_points(polyline: np.ndarray) -> np.ndarray:
    """Pixel positions -> OpenCV fixed-point vertices (a lone point drawn as a dot).

    Our pixel i spans [i, i + 1) with its centre at i + 0.5; OpenCV's pixel i is centred
    at integer i.
    """
    p = np.round((np.asarray(polyline, float).reshape(-1, 2) - 0.5) * (1 << _SHIFT))
    if len(p) == 1:
        p = np.repeat(p, 2, axis=0)  # OpenCV draws nothing for a single vertex
    return p.astype(np.int32).reshape(-1, 1, 2)


def _draw(out: np.ndarray, polylines: list[np.ndarray], values, thickness: int) -> np.ndarray:
    for line, value in zip(polylines, values, strict=False):
        if len(line):
            cv2.polylines(out, [_cv_points(line)], False, value, thickness, cv2.LINE_8, _SHIFT)
    return out


def rasterize(
    polylines: list[np.ndarray],
    width: int,
    height: int,
    values: list[float] | None = None,
    thickness: int = 1,
) -> np.ndarray:
    """Draw polylines into an (H, W) float32 map.

    Args:
        polylines: one (K, 2) array of pixel positions per stroke (x right, y down, the
            camera's pixel convention); a single point draws one pixel, none nothing.
        width, height: the map size in pixels.
        values: the value drawn for each polyline (default 1.0); where strokes cross,
            the later one's value wins.
        thickness: line width in pixels.
    Returns:
        (H, W) float32, 0 off the strokes.
    """
    if values is None:
        values = [1.0] * len(polylines)
    if len(values) != len(polylines):
        raise ValueError(f"{len(values)} values for {len(polylines)} polylines")
    return _draw(
        np.zeros((height, width), np.float32), polylines, [float(v) for v in values], thickness
    )


def rasterize_index(
    polylines: list[np.ndarray], width: int, height: int, thickness: int = 1
) -> np.ndarray:
    """Which stroke covers each pixel: (H, W) int32 polyline index, -1 off the strokes.

    Drawn exactly like `rasterize` (the later stroke wins where strokes cross), so
    `rasterize_index(...) >= 0` is `rasterize(...) != 0` for non-zero values.
    """
    return _draw(
        np.full((height, width), -1, np.int32), polylines, list(range(len(polylines))), thickness
    )
