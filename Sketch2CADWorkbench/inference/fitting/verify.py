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
are therefore ranked by `SketchFit.score`, closeness plus how far the strokes' ends lie
from the ends of the curves they draw (`end_gaps`).

    sketch_fit(solid, op, camera, strokes) -> SketchFit
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
# and their curves' (`SketchFit.score`): a pixel at an end weighs a pixel of closeness.
# Held-out level-3 add/sub and sweeps read alike with 0, 0.3 and 1, worse with 3 (sweeps'
# mean volume IoU .9532 -> .9491; see docs/measurements.md, verify.SCORE_END_WEIGHT).
SCORE_END_WEIGHT = 1.0
# A sample of the strokes or of the sketch farther than this (pixels) from the other is
# not explained by it (`SketchFit.strokes_unexplained`, `SketchFit.sketch_unexplained`).
EXPLAINED_PX = 4.0


@dataclass(frozen=True, eq=False)
class SketchFit:
    """How well an operation's own sketch (the lines the data generator draws for it) and
    the strokes explain each other, in pixels of the camera both are seen in: the one
    measure of a reading's fit, from which every figure the pipeline ranks, accepts or
    doubts a reading by is read.
    """

    to_sketch: np.ndarray  # (K,) each stroke sample's distance to the sketch
    to_strokes: np.ndarray  # (L,) each sketch sample's distance to the strokes
    end_gaps: np.ndarray  # (2M,) the open strokes' ends to those of the curves they draw

    # the figures `measures` reports, each a property
    MEASURES = (
        "misfit_px",
        "strokes_off_px",
        "sketch_off_px",
        "strokes_unexplained",
        "sketch_unexplained",
    )

    @classmethod
    def undrawn(cls) -> SketchFit:
        """The fit of an operation whose sketch cannot be drawn: infinitely far."""
        return cls(np.full(1, np.inf), np.full(1, np.inf), np.zeros(0))

    @property
    def misfit_px(self) -> float:
        """The symmetric mean distance: each direction's mean weighs alike, however many
        samples each has."""
        return 0.5 * (self.strokes_off_px + self.sketch_off_px)

    @property
    def strokes_off_px(self) -> float:
        """The strokes' samples' mean distance to the sketch."""
        return float(self.to_sketch.mean())

    @property
    def sketch_off_px(self) -> float:
        """The sketch's samples' mean distance to the strokes."""
        return float(self.to_strokes.mean())

    @property
    def strokes_unexplained(self) -> float:
        """The share of stroke samples over EXPLAINED_PX from the sketch."""
        return float(np.mean(self.to_sketch > EXPLAINED_PX))

    @property
    def sketch_unexplained(self) -> float:
        """The share of sketch samples over EXPLAINED_PX from the strokes."""
        return float(np.mean(self.to_strokes > EXPLAINED_PX))

    @property
    def score(self) -> float:
        """What readings are ranked by (lower is better): `misfit_px` plus SCORE_END_WEIGHT
        times the rms of the end gaps."""
        ends = self.end_gaps
        return self.misfit_px + (
            SCORE_END_WEIGHT * float(np.sqrt(np.mean(ends**2))) if len(ends) else 0.0
        )

    def measures(self) -> dict[str, float]:
        """The MEASURES by name."""
        return {k: getattr(self, k) for k in self.MEASURES}


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


def sketch_fit(
    solid: cq.Shape,
    op: Operation,
    camera: OrthoCamera,
    strokes: list[np.ndarray] | DrawnStrokes,
    seen: ContextMaps | None = None,
    face: ResolvedFace | None = None,
    whole: frozenset[int] = frozenset(),
) -> SketchFit:
    """How well op's projected curves and the strokes explain each other: the distances
    (pixels) from the strokes' samples to the curves, from the curves' samples to the
    strokes, and between the open strokes' ends and the ends of the open curves they
    draw (`end_gaps`).

    Args:
        strokes: the strokes, or their DrawnStrokes when several readings are scored.
        seen: maps of the model after op, rendered with `camera`: only the parts of op's
            curves that view sees count (every curve when None). When it sees none, or
            the curves lie wholly outside the image, the strokes are infinitely far from
            them.
        face: op.face resolved on `solid`, when the caller holds it (`operation_curves`).
        whole: with `seen`, the labels of the curves that count whole all the same
            (sketch/labels.py: a primitive's depth lines, which designers draw as depth
            cues where the view would hide them).
    """
    curves = operation_curves(solid, op, camera.basis()[2], face)
    if seen is not None:
        curves = [c for c in curves if c.label in whole] + visible_curves(
            [c for c in curves if c.label not in whole], camera, seen
        )
    shape = (camera.height, camera.width)
    drawn = strokes if isinstance(strokes, DrawnStrokes) else DrawnStrokes(strokes, shape)
    pixels = [camera.project(c.points)[0] for c in curves]
    target = stroke_pixels(pixels, shape)
    if not target.any():  # no curve seen, or every one outside the image
        return SketchFit(np.full(len(drawn.samples), np.inf), np.full(1, np.inf), np.zeros(0))
    ideal = np.concatenate([resample(p) for p in pixels])
    return SketchFit(
        DistanceField(target)(drawn.samples),
        drawn.field(ideal),
        end_gaps(
            [p for p, c in zip(pixels, curves, strict=False) if not c.closed], drawn.open_ends
        ),
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
