# SPDX-License-Identifier: LGPL-2.1-or-later
"""Auto-completion by symmetry: an operation reflected through a mid-plane of the shape.

The paper reflects a sketched primitive through a cross-section plane of the base
shape's oriented bounding box. Models here start from an axis-aligned box and every
operator keeps faces planar, so the planes are the bounding box's mid-planes
perpendicular to x, y or z.
"""

from __future__ import annotations

import cadquery as cq
import numpy as np

from .protocol import Operation

AXES = {"x": 0, "y": 1, "z": 2}


def mid_plane(solid: cq.Shape, axis: str) -> tuple[np.ndarray, np.ndarray]:
    """A point and unit normal of the bounding box's mid-plane perpendicular to `axis`."""
    if axis not in AXES:
        raise ValueError(f"symmetry plane must be one of {list(AXES)}, got {axis!r}")
    bb = solid.BoundingBox()
    centre = np.array([(bb.xmin + bb.xmax) / 2, (bb.ymin + bb.ymax) / 2, (bb.zmin + bb.zmax) / 2])
    n = np.zeros(3)
    n[AXES[axis]] = 1.0
    return centre, n


def _point(p, o, n) -> tuple[float, float, float]:
    p = np.asarray(p, float)
    return tuple(map(float, p - 2 * ((p - o) @ n) * n))


def _vector(v, n) -> tuple[float, float, float]:
    v = np.asarray(v, float)
    return tuple(map(float, v - 2 * (v @ n) * n))


def reflect(op: Operation, origin: np.ndarray, normal: np.ndarray) -> Operation:
    """The operation mirrored through the plane (origin, unit normal): its points and face
    normal reflected (`Operation.reflected`)."""
    return op.reflected(lambda p: _point(p, origin, normal), lambda v: _vector(v, normal))
