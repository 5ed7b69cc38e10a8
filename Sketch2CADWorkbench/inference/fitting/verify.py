# SPDX-License-Identifier: LGPL-2.1-or-later
"""How well a fitted operation explains the strokes: its own sketch, reprojected.

When two readings of the strokes both fit (the curve map's roles and the roles read
from geometry), the one whose curves (the lines the data generator would draw for it)
lie closer to the strokes, and the strokes to them, is the sketch's meaning. A designer
may also leave the hidden lines out: then the reading whose seen lines
(sketch/visible.py) match is the meaning, which tells a hole from the boss on its rim.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import cadquery as cq
import numpy as np

from ...brep.faces import ResolvedFace
from ...brep.protocol import Operation
from ...render.camera import OrthoCamera
from ...render.maps import ContextMaps
from ...sketch.curves import operation_curves
from ...sketch.visible import visible_curves
from .common import DistanceField, resample, stroke_pixels


@dataclass(frozen=True, eq=False)
class DrawnStrokes:
    """The strokes as readings are scored against them: their samples and the distance
    field to them, each made once (when first asked for) for all the readings of one
    sketch."""

    strokes: list[np.ndarray]   # pixel polylines of the camera the readings are seen in
    shape: tuple[int, int]      # that camera's (height, width)

    @cached_property
    def samples(self) -> np.ndarray:
        """(K, 2) points every pixel along the strokes."""
        return np.concatenate([resample(s) for s in self.strokes])

    @cached_property
    def field(self) -> DistanceField:
        """Distance to the pixels the strokes pass through."""
        return DistanceField(stroke_pixels(self.strokes, self.shape))


def sketch_distances(solid: cq.Shape, op: Operation, camera: OrthoCamera,
                     strokes: list[np.ndarray] | DrawnStrokes, seen: ContextMaps | None = None,
                     face: ResolvedFace | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Distances (pixels) from the strokes' samples to op's projected curves, and from
    the curves' samples to the strokes.

    Args:
        strokes: the strokes, or their DrawnStrokes when several readings are scored.
        seen: maps of the model after op, rendered with `camera`: only the parts of op's
            curves that view sees count (every curve when None). When it sees none, the
            strokes are infinitely far from them.
        face: op.face resolved on `solid`, when the caller holds it (`operation_curves`).
    """
    curves = operation_curves(solid, op, camera.direction, face)
    if seen is not None:
        curves = visible_curves(curves, camera, seen)
    shape = (camera.height, camera.width)
    drawn = strokes if isinstance(strokes, DrawnStrokes) else DrawnStrokes(strokes, shape)
    if not curves:
        return np.full(len(drawn.samples), np.inf), np.full(1, np.inf)
    pixels = [camera.project(c.points)[0] for c in curves]
    ideal = np.concatenate([resample(p) for p in pixels])
    return (DistanceField(stroke_pixels(pixels, shape))(drawn.samples),
            drawn.field(ideal))


def reprojection_error(solid: cq.Shape, op: Operation, camera: OrthoCamera,
                       strokes: list[np.ndarray], seen: ContextMaps | None = None) -> float:
    """Symmetric mean distance (pixels) between the strokes and op's projected curves
    (with `seen`, the parts of them the view sees: `sketch_distances`)."""
    return mean_distance(sketch_distances(solid, op, camera, strokes, seen))


def mean_distance(distances: tuple[np.ndarray, np.ndarray]) -> float:
    """The symmetric mean distance (pixels) of `sketch_distances`' two arrays."""
    to_sketch, to_strokes = distances
    return 0.5 * (float(to_sketch.mean()) + float(to_strokes.mean()))
