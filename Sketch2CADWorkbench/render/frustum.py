# SPDX-License-Identifier: LGPL-2.1-or-later
"""Choosing cameras: the paper's context frustum around a sketch, and framing a shape."""

from __future__ import annotations

import cadquery as cq
import numpy as np

from .camera import OrthoCamera
from .mesh import FaceMesh

MIN_EXTENT_PX = 8.0  # a dot-like sketch still gets a sensible context window


def context_camera(
    view: OrthoCamera, stroke_pixels: np.ndarray, factor: float = 2.0, size: int = 256
) -> OrthoCamera:
    """The context view: a square `factor` times the sketch's bounding box, centred on it.

    The paper renders the context maps in a frustum twice the size of the sketch's 2D
    bounding box; the larger side of the box sets the square's side, and a sketch
    smaller than MIN_EXTENT_PX pixels counts as that large.

    Args:
        view: the camera the strokes were drawn in.
        stroke_pixels: (N, 2) all stroke points, in `view`'s pixels.
        factor: frustum side relative to the bounding box's larger side (2 in the paper).
        size: the context maps' width and height in pixels.
    Returns:
        A camera with `view`'s direction and up, size x size pixels.
    Raises:
        ValueError: no stroke points.
    """
    p = np.asarray(stroke_pixels, float).reshape(-1, 2)
    if len(p) == 0:
        raise ValueError("a context frustum needs at least one stroke point")
    lo, hi = p.min(axis=0), p.max(axis=0)
    extent = max(float((hi - lo).max()), MIN_EXTENT_PX)
    centre = view.unproject(((lo + hi) / 2)[None], 0.0)[0]
    scale = 0.5 * extent * view.pixel_size * factor
    return OrthoCamera(tuple(map(float, centre)), view.direction, view.up, scale, size, size)


def fit_camera(
    shape: cq.Shape | FaceMesh | np.ndarray,
    direction,
    up=(0.0, 0.0, 1.0),
    margin: float = 1.1,
    size: int | tuple[int, int] = 256,
) -> OrthoCamera:
    """A view along `direction` in which the whole shape shows, centred.

    Args:
        shape: a solid (framed by its bounding box), a mesh (framed by its vertices,
            which is tighter) or a bounding box [[xmin, ymin, zmin], [xmax, ymax, zmax]]
            in mm.
        direction: view direction (world, from the eye into the scene).
        up: world vector that shows upwards.
        margin: visible extent over the shape's projected extent, along the image
            dimension the shape fills (1.1 leaves 5% of the shape's extent on each side).
        size: image side in pixels, or (width, height).
    Returns:
        The camera; its center is the middle of the shape's projected extent.
    """
    if isinstance(shape, FaceMesh):
        points = shape.vertices
    else:
        if isinstance(shape, cq.Shape):
            bb = shape.BoundingBox()
            lo, hi = np.array([bb.xmin, bb.ymin, bb.zmin]), np.array([bb.xmax, bb.ymax, bb.zmax])
        else:
            lo, hi = np.asarray(shape, float).reshape(2, 3)
        points = np.array(
            [[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
        )
    width, height = (size, size) if isinstance(size, int) else size
    probe = OrthoCamera((0.0, 0.0, 0.0), tuple(direction), tuple(up), 1.0, width, height)
    r, u, f = probe.basis()
    x, y, z = points @ r, points @ u, points @ f
    centre = (r * (x.min() + x.max()) + u * (y.min() + y.max()) + f * (z.min() + z.max())) / 2
    half_w, half_h = (x.max() - x.min()) / 2, (y.max() - y.min()) / 2
    scale = margin * max(half_h, half_w * height / width, 1e-9)
    return OrthoCamera(
        tuple(map(float, centre)),
        tuple(map(float, direction)),
        tuple(map(float, up)),
        float(scale),
        width,
        height,
    )
