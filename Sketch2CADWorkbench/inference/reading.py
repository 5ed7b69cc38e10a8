# SPDX-License-Identifier: LGPL-2.1-or-later
"""One fitted reading of a sketch step: how well it explains the strokes, and its result.

A reading is an operation fitted on one base face (`Reading`), with the SketchFit of its
own sketch (the lines the data generator draws for it) and the strokes; `doubts` says
whether that fit is too poor to trust; `builds_a_change` builds it and refuses a reading
whose Boolean fails or leaves the model as it was.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import cadquery as cq

from ..brep.faces import OperationError, model_scale
from ..brep.operators import apply_operation
from ..brep.protocol import Operation
from .context import Context
from .fitting.verify import SketchFit

# A reading is flagged as doubtful when a measure of its SketchFit passes its threshold
# here: the strokes' mean distance to the reading's own sketch, or the sketch's to the
# strokes (context pixels; their mean, misfit_px, then passes neither): each the 99.5%
# quantile of held-out level-1 sketches, rounded up (scripts/misfit_threshold.py); or the
# classifier's probability of the operator read below search.OVERRULE_PROB, the least
# with which another operator may replace its own: the search fell back to an operator
# the networks all but rule out, as it does for scribbles, and its sketch does not fit
# the strokes clearly (misfit_px over GOOD_FIT_PX; no scribble's reading came within 6 px,
# where a hole drawn without its hidden lines, which the networks take for an extrusion,
# reads within 1-3 px). See docs/measurements.md, reading.DOUBT.
DOUBT = {"strokes_off_px": 7.7, "sketch_off_px": 7.7, "confidence": 1e-3}
# What a doubt rule may read (`doubt_measures`).
DOUBT_MEASURES = (*SketchFit.MEASURES, "confidence")
# A result whose volume (and bounding box, in model diagonals) differs from the model's by
# less than this share is the model unchanged: such a step is refused.
SAME_VOLUME = 1e-6
# A reading whose own sketch lies within this (context pixels, mean both ways) of the
# strokes is a clear fit: it ends the search over faces and operators (search.py), and
# snapping keeps an operation moved only where it still fits so (see
# docs/measurements.md, reading.GOOD_FIT_PX).
GOOD_FIT_PX = 3.0


Fit = tuple[Operation, int, list[int]]  # an operation, the face it stands on, stroke labels


def doubt_measures(fit: SketchFit, confidence: float) -> dict[str, float]:
    """What a doubt rule reads of a reading: its SketchFit's MEASURES and the classifier's
    probability of its operator ("confidence")."""
    return {**fit.measures(), "confidence": float(confidence)}


def doubts(measures: dict[str, float]) -> list[str]:
    """The measures (`doubt_measures`) past their DOUBT thresholds: above it, the
    confidence below it where the sketch does not fit the strokes within GOOD_FIT_PX. A
    reading with any is doubtful: scribbles are otherwise read as
    something. Each threshold is set on held-out level-1 sketches
    (scripts/misfit_threshold.py; see docs/measurements.md, reading.DOUBT); the measures DOUBT
    leaves out tell scribbles from real sketches less well."""
    return [
        k
        for k, limit in DOUBT.items()
        if (
            measures[k] < limit and measures["misfit_px"] > GOOD_FIT_PX
            if k == "confidence"
            else measures[k] > limit
        )
    ]


@dataclass
class Reading:
    """One base face's fitted operation: how well its own sketch and the strokes explain
    each other, whether it is hidden from the sketch view (its face, or a primitive's base
    behind the model), and (once built) the result."""

    fit: SketchFit
    op: Operation
    index: int
    labels: list[int]
    hidden: bool
    result: cq.Solid | None = None
    refused: str = ""  # why it cannot be the step: its Boolean fails or changes nothing
    # read with the other Boolean because none with the first built: no flip back to it
    flip_refused: bool = False
    # its other Boolean's reading when that explains the strokes too (alternative.py)
    alternative: Reading | None = None
    # a built primitive's fits with its lines drawn each of alternative.LINE_WAYS, of
    # which `fit` is the best; () for other readings
    ways: tuple[SketchFit, ...] = ()

    @property
    def doubtful(self) -> bool:
        """Its own sketch and the strokes lie apart past DOUBT (`doubts`; the classifier's
        confidence is the search's to weigh, not asked here)."""
        return bool(doubts(doubt_measures(self.fit, 1.0)))


def leaves_unchanged(before: cq.Shape, after: cq.Shape) -> bool:
    """Whether a step's result is the model it started from: the same volume (within
    SAME_VOLUME of it), bounding box and number of faces (a primitive wholly in the air,
    cut away, or wholly inside the model, added)."""
    vb = float(before.Volume())
    if abs(float(after.Volume()) - vb) > SAME_VOLUME * vb:
        return False
    tol = SAME_VOLUME * model_scale(before)
    a, b = before.BoundingBox(), after.BoundingBox()
    box = lambda bb: (bb.xmin, bb.ymin, bb.zmin, bb.xmax, bb.ymax, bb.zmax)  # noqa: E731
    return all(abs(x - y) <= tol for x, y in zip(box(a), box(b), strict=True)) and len(
        before.Faces()
    ) == len(after.Faces())


def builds_a_change(solid: cq.Shape, reading: Reading, ctx: Context) -> bool:
    """Build the reading's operation; keep the result, or say why it cannot be the step
    (the time goes to ctx.build_s)."""
    if reading.result is None and not reading.refused:
        start = time.perf_counter()
        try:
            op = reading.op
            # a planar f is held (resolved while the reading was scored), a curved one
            # resolved where the step stands
            held = None if op.face.surface.curved else ctx.resolved(solid, op.face).face
            result = apply_operation(solid, op, held)
        except OperationError as e:
            reading.refused = str(e)
        else:
            if leaves_unchanged(solid, result):
                reading.refused = (
                    f"the {reading.op.type.value} it reads would leave the model "
                    "as it is (it adds or removes nothing there); draw it over "
                    "the face it stands on"
                )
            else:
                reading.result = result
        finally:
            ctx.build_s += time.perf_counter() - start
    return reading.result is not None
