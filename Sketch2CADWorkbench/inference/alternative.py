# SPDX-License-Identifier: LGPL-2.1-or-later
"""Which Boolean a primitive's strokes mean, and the other one when it explains them too.

Drawn with every line, a boss on f and a hole into f whose rim is the boss's top outline
draw the same lines in a parallel view (paper, Fig. 5b). Designers leave out the lines
the view hides, and then the two differ: a hole's material hides the near part of its
floor outline (and all of a deep hole's depth lines and floor), a boss hides the back of
its own base outline (sketch/visible.py). Many draw a drilled hole's depth lines all the
same, as depth cues, with the far part of its floor circle. So every built primitive
reading is scored by its lines drawn each of LINE_WAYS (`drawn_fits`: every line, only
those its own result lets the view see, or those with its depth lines whole) and kept
with the way that explains the strokes best (`explained`, `SketchFit.score`); the search
ranks it so against other operators' readings. A reading and its other Boolean are
weighed by their scores with the lines drawn the one way that explains the strokes
best for either (`one_way_scores`): were each allowed its better way, the boss would
explain a seen-drawn hole by every line nearly as well as the hole, the lines it adds
being the few a shallow hole hides. Of a reading and its other Boolean, the other is
taken when it explains the strokes better by more than TIE_PX and stands on f as fully
as the fitted one (its base outline's share on f at least the fitted one's, up to
`primitive.ON_FACE_FRACTION`), or, standing on f by half at least, explains them with
under half the fitted one's misfit (OUTWEIGH): drawn as a cylinder shows itself, a
hole's floor outline loses the half its own cylinder hides, just as the boss standing
on that floor outline slid back along the view onto f would (its base's back half), so
the lines alone may favour that boss, which then stands off f's outline where the
hole's rim lies on f.
Within TIE_PX the strokes do not tell them apart, and the fitted choice stands
(`primitive.choose_option`: where each would stand on f). The one not taken is offered
as the alternative when it builds and explains the strokes within OFFER_PX of the one
taken (or within that one's own score of it).
"""

from __future__ import annotations

from dataclasses import dataclass

import cadquery as cq
import numpy as np

from ..brep.faces import OperationError
from ..brep.protocol import AddSubPrism, Mode, Operation, Sweep
from ..render.camera import OrthoCamera
from ..render.maps import MapRenderer
from ..sketch.labels import PROFILE
from .fitting.primitive import ON_FACE_FRACTION
from .fitting.verify import DrawnStrokes, SketchFit, sketch_fit
from .mirror import apply_with_symmetry

# A reading's other Boolean replaces it only when it explains the strokes better by more
# than this (pixels of SketchFit.score): a level-1 hand's median misfit is 1.4 px, so a
# lead of a pixel is the strokes' own word, not the hand's noise.
TIE_PX = 1.0
# The reading not taken is offered when its score lies within this (pixels) of the one
# taken, or within the taken one's own score of it: a clear fit's margin
# (reading.GOOD_FIT_PX), wider than TIE_PX so that the one click stays offered where the
# strokes lean one way but the hand could mean the other, and wider still where the
# taken reading itself explains the strokes poorly (a hole drawn without its hidden
# lines, fitted as if every line were drawn). See docs/measurements.md,
# alternative.TIE_PX and OFFER_PX.
OFFER_PX = 3.0
# Where each would stand on f gives way to the strokes when the other Boolean stands on
# f at least by half (OUTWEIGH_SHARE of its base outline) and explains them with under
# 1/OUTWEIGH of the reading's misfit: a boss whose seen lines miss the strokes by 30 px
# is not what was drawn, even if the hole that explains them within 10 spills past f's
# edge by the hand's error (drawn near it, its rim fitted a little wide). A primitive
# standing mostly off f is no such spill: drawn with every line, a hole's strokes are
# explained by the boss slid off f along the view as closely (paper, Fig. 5b).
OUTWEIGH = 2.0
OUTWEIGH_SHARE = 0.5


@dataclass(frozen=True, eq=False)
class Alternative:
    """Another reading of the same strokes, the other Boolean of the one taken: it builds
    and explains the strokes within OFFER_PX of it, so one click may take it instead."""

    operations: tuple[Operation, ...]  # as Interpretation.operations (its mirror image too)
    solid: cq.Solid  # the model with them applied
    score_px: float  # how well it explains the strokes (`SketchFit.score` of `explained`)
    option: Mode  # its Boolean (the designer's choice that reads it)

    @staticmethod
    def of(
        solid: cq.Shape, op: Operation, result: cq.Solid, score_px: float, symmetry: str | None
    ) -> Alternative | None:
        """The alternative of op, built on `solid` as `result`, with its mirror image
        through the mid-plane `symmetry` if asked (`mirror.apply_with_symmetry`); None
        when that image does not build, or op is no primitive (it has no Boolean)."""
        if not isinstance(op, (AddSubPrism, Sweep)):
            return None
        try:
            ops, solid = apply_with_symmetry(solid, op, symmetry, result)
        except OperationError:
            return None
        return Alternative(ops, solid, score_px, op.mode)


# The ways a designer draws a primitive's lines, each scored (`drawn_fits`): every line
# (the paper's sketches); only what its result lets the view see; or that with its depth
# lines (side edges, a sweep's profile lines) whole, as depth cues, where the view
# hides them (a drilled hole's sides behind its rim).
LINE_WAYS = ("every", "seen", "seen with depth lines")


def drawn_fits(
    solid: cq.Shape,
    op: Operation,
    result: cq.Shape,
    camera: OrthoCamera,
    drawn: DrawnStrokes,
    renderer: MapRenderer,
    face=None,
    every: SketchFit | None = None,
) -> tuple[SketchFit, ...]:
    """`verify.sketch_fit` of op's lines drawn each of the LINE_WAYS, the seen ones those
    the view sees of its `result` (`every`: the fit with every line, when known)."""
    seen = renderer.render(result, camera)
    return (
        every or sketch_fit(solid, op, camera, drawn, face=face),
        sketch_fit(solid, op, camera, drawn, seen, face),
        sketch_fit(solid, op, camera, drawn, seen, face, frozenset({PROFILE})),
    )


def explained(fits: tuple[SketchFit, ...]) -> SketchFit:
    """Of a reading's fits with its lines drawn each way (`drawn_fits`), the one that
    explains the strokes best (`SketchFit.score`)."""
    return min(fits, key=lambda fit: fit.score)


def one_way_scores(
    first: tuple[SketchFit, ...], other: tuple[SketchFit, ...]
) -> tuple[float, float]:
    """The `SketchFit.score`s of two readings, each given as its fits with its lines
    drawn each way (`drawn_fits`), both with the lines drawn the way in which either
    reading explains the strokes best."""
    scores = np.array([[fit.score for fit in fits] for fits in (first, other)])
    way = int(np.argmin(scores.min(axis=0)))
    return float(scores[0, way]), float(scores[1, way])


def the_meant(first: float, other: float, shares: tuple[float, float]) -> tuple[bool, bool]:
    """Of a reading scoring `first` and its other Boolean scoring `other`
    (`one_way_scores`), their base outlines' `shares` on f (`primitive.base_share`):
    whether the other is the meaning, and whether the one not taken is offered as the
    alternative. The other must stand on f as fully as the reading (up to
    `primitive.ON_FACE_FRACTION`), or at least by half where it outweighs the reading
    (OUTWEIGH)."""
    stands = shares[1] >= min(shares[0], ON_FACE_FRACTION) or (
        shares[1] >= OUTWEIGH_SHARE and OUTWEIGH * other < first
    )
    flip = stands and other < first - TIE_PX
    taken, left = (other, first) if flip else (first, other)
    return flip, left - taken <= max(OFFER_PX, taken)
