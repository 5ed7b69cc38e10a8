# SPDX-License-Identifier: LGPL-2.1-or-later
"""One fitted reading of a sketch step: how well it explains the strokes, and its result.

A reading is an operation fitted on one base face (`Reading`), scored by how far its own
sketch (the lines the data generator draws for it) lies from the strokes; `SketchFit`
says whether that is close enough to trust; `builds_a_change` builds it and refuses a
reading whose Boolean fails or leaves the model as it was.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import cadquery as cq
import numpy as np

from ..brep.faces import OperationError, model_scale
from ..brep.operators import apply_operation
from ..brep.protocol import Operation
from ..render.camera import OrthoCamera
from .alternative import explained
from .context import Context
from .fitting.verify import mean_distance, reading_score, sketch_distances

# A reading is flagged as doubtful when a measure of SketchFit passes its threshold
# here (context pixels): the strokes' mean distance to the reading's own sketch, or the
# sketch's to the strokes (their mean, misfit_px, then passes neither): each the 99.5%
# quantile of held-out level-1 sketches, rounded up (scripts/misfit_threshold.py; see
# docs/measurements.md, reading.DOUBT).
DOUBT = {"strokes_off_px": 7.7, "sketch_off_px": 7.7}
# A sample of the strokes or of the sketch farther than this (context pixels) from the
# other is not explained by it.
EXPLAINED_PX = 4.0
# A result whose volume (and bounding box, in model diagonals) differs from the model's by
# less than this share is the model unchanged: such a step is refused.
SAME_VOLUME = 1e-6
# A reading whose own sketch lies within this (context pixels, mean both ways) of the
# strokes is a clear fit: it ends the search over faces and operators (search.py), and
# snapping keeps an operation moved only where it still fits so (see
# docs/measurements.md, reading.GOOD_FIT_PX).
GOOD_FIT_PX = 3.0


Fit = tuple[Operation, int, list[int]]  # an operation, the face it stands on, stroke labels


@dataclass(frozen=True)
class SketchFit:
    """How well a reading's own sketch (the lines the data generator draws for it)
    explains the strokes, and the strokes it: scribbles are otherwise read as something.

    A reading is doubtful when any measure passes its threshold in DOUBT (above it; the
    confidence below it), each set on held-out level-1 sketches
    (scripts/misfit_threshold.py; see docs/measurements.md, reading.DOUBT). The measures DOUBT
    leaves out tell scribbles from real sketches less well.
    """

    misfit_px: float  # symmetric mean distance between strokes and sketch
    strokes_off_px: float  # mean distance of the strokes' samples to the sketch
    sketch_off_px: float  # mean distance of the sketch's samples to the strokes
    strokes_unexplained: float  # share of stroke samples over EXPLAINED_PX from the sketch
    sketch_unexplained: float  # share of sketch samples over EXPLAINED_PX from the strokes
    confidence: float  # the classifier's probability of the operator read

    MEASURES = (
        "misfit_px",
        "strokes_off_px",
        "sketch_off_px",
        "strokes_unexplained",
        "sketch_unexplained",
        "confidence",
    )

    @staticmethod
    def of(
        solid: cq.Shape,
        op: Operation,
        camera: OrthoCamera,
        strokes: list[np.ndarray],
        confidence: float,
    ) -> "SketchFit":
        return SketchFit.of_distances(*sketch_distances(solid, op, camera, strokes)[:2], confidence)

    @staticmethod
    def of_distances(
        to_sketch: np.ndarray, to_strokes: np.ndarray, confidence: float
    ) -> "SketchFit":
        """From `verify.sketch_distances`' first two arrays."""
        return SketchFit(
            mean_distance((to_sketch, to_strokes)),
            float(to_sketch.mean()),
            float(to_strokes.mean()),
            float(np.mean(to_sketch > EXPLAINED_PX)),
            float(np.mean(to_strokes > EXPLAINED_PX)),
            float(confidence),
        )

    def to_dict(self) -> dict[str, float]:
        return {k: getattr(self, k) for k in self.MEASURES}

    def passed(self) -> list[str]:
        """The measures past their DOUBT thresholds."""
        return [
            k
            for k, limit in DOUBT.items()
            if (getattr(self, k) < limit if k == "confidence" else getattr(self, k) > limit)
        ]

    @property
    def doubtful(self) -> bool:
        return bool(self.passed())


@dataclass
class Reading:
    """One base face's fitted operation: how far its own sketch lies from the strokes,
    whether it is hidden from the sketch view (its face, or a primitive's base behind the
    model), and (once built) the result."""

    distances: tuple[np.ndarray, np.ndarray, np.ndarray]  # `verify.sketch_distances`
    op: Operation
    index: int
    labels: list[int]
    hidden: bool
    result: cq.Solid | None = None
    refused: str = ""  # why it cannot be the step: its Boolean fails or changes nothing
    # read with the other Boolean because none with the first built: no flip back to it
    flip_refused: bool = False
    # `distances` of the lines its result lets the view see, once weighed against its
    # other Boolean (`search.weigh_the_other_boolean`); None until then
    seen: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
    # its other Boolean's reading when that explains the strokes too (alternative.py)
    alternative: Reading | None = None

    @property
    def explained(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """`distances` or `seen`, whichever explains the strokes better
        (`alternative.explained`)."""
        return explained(self.distances, self.seen)

    @property
    def error(self) -> float:
        """Symmetric mean distance (pixels) of `explained`, `verify.mean_distance`."""
        return mean_distance(self.explained)

    @property
    def score(self) -> float:
        """What readings are ranked by (pixels), `verify.reading_score` of `explained`."""
        return reading_score(self.explained)

    @property
    def doubtful(self) -> bool:
        """Its own sketch and the strokes lie apart past DOUBT (SketchFit)."""
        return SketchFit.of_distances(*self.explained[:2], 1.0).doubtful


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
    return all(abs(x - y) <= tol for x, y in zip(box(a), box(b))) and len(before.Faces()) == len(
        after.Faces()
    )


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
