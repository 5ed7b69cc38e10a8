# SPDX-License-Identifier: LGPL-2.1-or-later
"""How well a fitted operation explains the strokes: its own sketch, reprojected.

When two readings of the strokes both fit (the curve map's roles and the roles read
from geometry), the one whose curves (the lines the data generator would draw for it)
lie closer to the strokes, and the strokes to them, is the sketch's meaning. A designer
may also leave the hidden lines out: then the reading whose seen lines
(sketch/visible.py) match is the meaning, which tells a hole from the boss on its rim.

Closeness alone favours a reading that follows each stroke where the hand displaced it:
the hand the data generator models (datagen/strokes.py) misses a curve's two ends by
Gaussian noise and spreads that linearly along the stroke, so a stroke is its curve
displaced, and its ends tell where the curve's ends are. The readings of one operator
are therefore ranked by `reading_score`, closeness plus how far the strokes' ends lie
from the ends of the curves they draw (`end_gaps`).
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
from .common import (
    DistanceField,
    end_order,
    match_ends,
    open_ends,
    resample,
    stroke_pixels,
)

# Readings are ranked by closeness plus this times the rms gap between the strokes' ends
# and their curves' (`reading_score`): a pixel at an end weighs a pixel of closeness
# (docs/measurements.md, verify.END_WEIGHT).
END_WEIGHT = 1.0


@dataclass(frozen=True, eq=False)
class DrawnStrokes:
    """The strokes as readings are scored against them: their samples and the distance
    field to them, each made once (when first asked for) for all the readings of one
    sketch."""

    strokes: list[np.ndarray]  # pixel polylines of the camera the readings are seen in
    shape: tuple[int, int]  # that camera's (height, width)

    @cached_property
    def samples(self) -> np.ndarray:
        """(K, 2) points every pixel along the strokes."""
        return np.concatenate([resample(s) for s in self.strokes])

    @cached_property
    def open_ends(self) -> np.ndarray:
        """(S, 2, 2) the ends of the strokes that are not loops (`open_ends`)."""
        return open_ends(self.strokes)

    @cached_property
    def field(self) -> DistanceField:
        """Distance to the pixels the strokes pass through."""
        return DistanceField(stroke_pixels(self.strokes, self.shape))


def sketch_distances(
    solid: cq.Shape,
    op: Operation,
    camera: OrthoCamera,
    strokes: list[np.ndarray] | DrawnStrokes,
    seen: ContextMaps | None = None,
    face: ResolvedFace | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Distances (pixels) from the strokes' samples to op's projected curves, from the
    curves' samples to the strokes, and between the open strokes' ends and the ends of
    the open curves they draw (`end_gaps`).

    Args:
        strokes: the strokes, or their DrawnStrokes when several readings are scored.
        seen: maps of the model after op, rendered with `camera`: only the parts of op's
            curves that view sees count (every curve when None). When it sees none, or
            the curves lie wholly outside the image, the strokes are infinitely far from
            them.
        face: op.face resolved on `solid`, when the caller holds it (`operation_curves`).
    """
    curves = operation_curves(solid, op, camera.direction, face)
    if seen is not None:
        curves = visible_curves(curves, camera, seen)
    shape = (camera.height, camera.width)
    drawn = strokes if isinstance(strokes, DrawnStrokes) else DrawnStrokes(strokes, shape)
    pixels = [camera.project(c.points)[0] for c in curves]
    target = stroke_pixels(pixels, shape)
    if not target.any():  # no curve seen, or every one outside the image
        return np.full(len(drawn.samples), np.inf), np.full(1, np.inf), np.zeros(0)
    ideal = np.concatenate([resample(p) for p in pixels])
    return (
        DistanceField(target)(drawn.samples),
        drawn.field(ideal),
        end_gaps([p for p, c in zip(pixels, curves) if not c.closed], drawn.open_ends),
    )


def end_gaps(curves: list[np.ndarray], ends: np.ndarray) -> np.ndarray:
    """How far (pixels) the open strokes' ends lie from the ends of the open curves they
    draw, each stroke matched to one curve (`match_ends`).

    Args:
        curves: the open curves' pixel polylines.
        ends: (S, 2, 2) the open strokes' first and last points (`open_ends`).
    Returns:
        (2M,) the gaps at both ends of the M matched strokes (empty when none match).
    """
    heads = np.array([[c[0], c[-1]] for c in curves], float).reshape(-1, 2, 2)
    rows, cols, swapped = match_ends(heads, ends)
    meant = heads[cols[:, None], end_order(swapped)]  # (M, 2, 2)
    return np.linalg.norm(ends[rows] - meant, axis=2).ravel()


def reprojection_error(
    solid: cq.Shape,
    op: Operation,
    camera: OrthoCamera,
    strokes: list[np.ndarray],
    seen: ContextMaps | None = None,
) -> float:
    """Symmetric mean distance (pixels) between the strokes and op's projected curves
    (with `seen`, the parts of them the view sees: `sketch_distances`)."""
    return mean_distance(sketch_distances(solid, op, camera, strokes, seen))


def mean_distance(distances: tuple[np.ndarray, ...]) -> float:
    """The symmetric mean distance (pixels) of `sketch_distances`' first two arrays."""
    to_sketch, to_strokes = distances[:2]
    return 0.5 * (float(to_sketch.mean()) + float(to_strokes.mean()))


def reading_score(distances: tuple[np.ndarray, np.ndarray, np.ndarray]) -> float:
    """How well a reading explains the strokes (pixels, lower is better): the symmetric
    mean distance plus END_WEIGHT times the rms of the end gaps (`sketch_distances`)."""
    ends = distances[2]
    return mean_distance(distances) + (
        END_WEIGHT * float(np.sqrt(np.mean(ends**2))) if len(ends) else 0.0
    )
