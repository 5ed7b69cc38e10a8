# SPDX-License-Identifier: LGPL-2.1-or-later
"""How well a fitted operation explains the strokes: its own sketch, reprojected.

When two readings of the strokes both fit (the curve map's roles and the roles read
from geometry), the one whose curves (the lines the data generator would draw for it)
lie closer to the strokes, and the strokes to them, is the sketch's meaning.
"""
from __future__ import annotations

import cadquery as cq
import numpy as np

from ...brep.protocol import Operation
from ...render.camera import OrthoCamera
from ...sketch.curves import operation_curves
from .common import DistanceField, resample, stroke_pixels


def sketch_distances(solid: cq.Shape, op: Operation, camera: OrthoCamera,
                     strokes: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Distances (pixels) from the strokes' samples to op's projected curves, and from
    the curves' samples to the strokes."""
    shape = (camera.height, camera.width)
    curves = [camera.project(c.points)[0] for c in operation_curves(solid, op, camera.direction)]
    drawn = np.concatenate([resample(s) for s in strokes])
    ideal = np.concatenate([resample(c) for c in curves])
    return (DistanceField(stroke_pixels(curves, shape))(drawn),
            DistanceField(stroke_pixels(strokes, shape))(ideal))


def reprojection_error(solid: cq.Shape, op: Operation, camera: OrthoCamera,
                       strokes: list[np.ndarray]) -> float:
    """Symmetric mean distance (pixels) between the strokes and op's projected curves."""
    to_sketch, to_strokes = sketch_distances(solid, op, camera, strokes)
    return 0.5 * (float(to_sketch.mean()) + float(to_strokes.mean()))
