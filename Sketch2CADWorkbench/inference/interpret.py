# SPDX-License-Identifier: LGPL-2.1-or-later
"""The interpret pipeline: strokes and camera -> maps -> networks -> fitting -> operation.

    interpret(solid, strokes, view, predictor) -> Interpretation

The strokes are pixel polylines in the designer's view. The context camera frames
twice the sketch's bounding box (paper, Sec. 4); the context solid is rendered there
to D, N and face IDs; the predictor classifies the operator and segments the base
face F and the curves C; fitting turns those into an operation; the operation is
applied to a copy of the solid. Any failure raises InterpretError with the reason,
and the caller's solid is untouched.

The stages, each in its module:

    context.py    the strokes checked and framed, the model rendered (the networks' inputs)
    search.py     the search over operators and base faces, ended by a clear fit
    adapters.py   each operator's fitting on one base face
    reading.py    a fitted reading, how well its sketch explains the strokes, its result
    mirror.py     the step's mirror image
    interpret.py  the chosen reading snapped (regularization), the other Boolean offered,
                  the Interpretation assembled
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import cadquery as cq
import numpy as np

from ..brep.faces import OperationError, face_at
from ..brep.operators import apply_operation
from ..brep.protocol import Mode, Operation, OperatorType
from ..render.camera import OrthoCamera
from ..render.maps import MapRenderer
from ..sketch.labels import LABELLED
from ..sketch.segment import segment_strokes
from .alternative import Alternative, drawn_fits, explained
from .context import Context, InterpretError, check_sketch, to_context
from .fitting.common import FitError
from .fitting.regularize import Snap, StrokeCheck, hand_tolerance, regularize_operation
from .fitting.verify import SketchFit, sketch_fit
from .mirror import apply_with_symmetry
from .options import InterpretOptions
from .reading import GOOD_FIT_PX, Reading, doubt_measures, doubts
from .search import (
    TAKE_A_BOOLEAN,
    Predictor,
    classifies_the_shell,
    read_operators,
    shell_prior,
)


@dataclass
class Interpretation:
    """What a sketch step was read as, and the resulting solid."""

    operations: tuple[Operation, ...]  # the operation, then its mirror image if asked
    solid: cq.Solid
    op_type: OperatorType
    probabilities: dict[str, float]  # per operator read; the shell's only where proposed
    base_face: int
    stroke_labels: list[int]  # one per piece of curve read (sketch/segment.py)
    camera: OrthoCamera  # the context camera (maps' pixels)
    # ms per stage: render, networks, fitting, brep (every Boolean built: the readings'
    # results, which fitting builds to refuse one that fails or changes nothing, and the
    # step's mirror image or regularized rebuild) and total
    timings_ms: dict[str, float] = field(default_factory=dict)
    # The other Boolean's reading when it explains the same strokes too (a boss on f and
    # a hole into f draw the same lines in a parallel view, paper Fig. 5b): alternative.py
    alternative: Alternative | None = None
    # How well the operation's own sketch and the strokes explain each other.
    fit: SketchFit | None = None
    # The snaps regularization applied, in order (InterpretOptions.skip_snaps undoes one).
    snaps: tuple[Snap, ...] = ()
    # Why the snaps found were not applied (the snapped shape does not build); "" if none.
    unsnapped: str = ""
    # The shell was proposed by the strokes closing into a rim (`search.shell_prior`), not
    # by the classifier, which has no shell class: its entry in `probabilities` is the
    # likeliest class's, no probability of its own.
    shell_by_rim: bool = False

    @property
    def classified(self) -> dict[str, float]:
        """The classifier's own probabilities, per operator (`probabilities` without a
        shell proposed by its rim)."""
        return {
            k: v
            for k, v in self.probabilities.items()
            if not (self.shell_by_rim and k == OperatorType.SHELL.value)
        }

    @property
    def other_option(self) -> Mode | None:
        """The Boolean that reads the strokes too (the alternative's); None when none does."""
        return self.alternative.option if self.alternative else None

    @property
    def confidence(self) -> float:
        """The classifier's probability of the operator read."""
        return self.probabilities[self.op_type.value]

    def measures(self) -> dict[str, float]:
        """What the doubt rule reads (`reading.doubt_measures`); {} without a fit."""
        return {} if self.fit is None else doubt_measures(self.fit, self.confidence)

    @property
    def doubtful(self) -> bool:
        """The strokes do not look like this operation (`reading.doubts`): say so
        (`doubt()`), and add it only when the user accepts it."""
        return self.fit is not None and bool(doubts(self.measures()))

    def doubt(self) -> str:
        """The warning for a doubtful reading ("" when it is not)."""
        if not self.doubtful:
            return ""
        m, what = self.measures(), self.op_type.value
        why = {
            "misfit_px": f"its own sketch lies {m['misfit_px']:.1f} px from them",
            "strokes_off_px": f"the strokes lie {m['strokes_off_px']:.1f} px from its sketch",
            "sketch_off_px": f"its sketch lies {m['sketch_off_px']:.1f} px from the strokes",
            "strokes_unexplained": f"{m['strokes_unexplained']:.0%} of the strokes are not "
            "lines of it",
            "sketch_unexplained": f"{m['sketch_unexplained']:.0%} of its lines were not drawn",
            "confidence": f"the networks give a {what} a probability of only {m['confidence']:.2g}",
        }
        return (
            f"the strokes do not look much like this {what}: "
            + "; ".join(why[k] for k in doubts(m))
            + " (beyond 99.5% of held-out synthetic sketches); check it, or clear and "
            "draw again"
        )


def snap_or_keep(
    solid: cq.Shape,
    op: Operation,
    face: cq.Face,
    fit_of: Callable[[Operation], SketchFit],
    context: OrthoCamera,
    view: OrthoCamera,
    options: InterpretOptions,
) -> tuple[Operation, tuple[Snap, ...], cq.Solid | None, str]:
    """A fitted operation regularized within the hand's tolerance (`hand_tolerance` of
    its misfit) and built: the operation, its snaps, its result and "". When nothing
    snaps, or the snapped operation does not build (a snapped sweep OCCT calls invalid):
    `op` itself, no snaps, None (the caller holds its result) and why not, if it did not
    build. Snapping never costs a reading that builds.

    `fit_of(op)`: an operation's SketchFit to the strokes in pixels of the `context` camera
    it was fitted in. Snapping asks it of the operations it moves (`StrokeCheck`, a clear
    fit within GOOD_FIT_PX; one whose sketch cannot be drawn lies infinitely far): a
    target beyond the tolerance, or a round length, is taken where the strokes still fit
    the operation moved there."""

    def fit_or_undrawn(moved: Operation) -> SketchFit:
        try:
            return fit_of(moved)
        except OperationError:
            return SketchFit.undrawn()

    tol = hand_tolerance(options.snap_px, fit_of(op).misfit_px, context, view)
    reg = regularize_operation(
        solid,
        op,
        face,
        view,
        options.snap_step,
        tol,
        options.skip_snaps,
        StrokeCheck(fit_or_undrawn, GOOD_FIT_PX),
    )
    if not reg.snaps:
        return op, (), None, ""
    try:
        return reg.operation, reg.snaps, apply_operation(solid, reg.operation), ""
    except OperationError as e:
        return op, (), None, f"snapped, it would not build ({e}), so it stays as drawn"


def _snapped(
    solid: cq.Shape, reading: Reading, ctx: Context, view: OrthoCamera, options: InterpretOptions
) -> tuple[Operation, tuple[Snap, ...], cq.Solid, str]:
    """`snap_or_keep` for a reading, its result the reading's own when it is kept (the
    rebuild goes to ctx.build_s)."""
    start = time.perf_counter()
    op, snaps, result, why = snap_or_keep(
        solid,
        reading.op,
        face_at(solid, reading.index),
        lambda moved: ctx.sketch_fit(solid, moved),
        ctx.camera,
        view,
        options,
    )
    ctx.build_s += time.perf_counter() - start
    return op, snaps, reading.result if result is None else result, why


def _among(probs: np.ndarray, kinds: list[OperatorType]) -> np.ndarray:
    """The classifier's probabilities given that the operator is one of `kinds` (the
    others 0): its belief among the primitives a chosen Boolean allows, however sure it
    is of another operator."""
    keep = np.zeros_like(probs)
    index = [LABELLED.index(k) for k in kinds]
    keep[index] = probs[index]
    total = float(keep.sum())
    return keep / total if total > 0 else probs


def interpret(
    solid: cq.Shape,
    strokes: list[np.ndarray],
    view: OrthoCamera,
    predictor: Predictor,
    renderer: MapRenderer | None = None,
    options: InterpretOptions = InterpretOptions(),
    op_type: OperatorType | None = None,
) -> Interpretation:
    """Read one sketch step over `solid` as an operation and apply it.

    Args:
        solid: the current model (not modified).
        strokes: pixel polylines (K, 2) in `view`'s pixels, in any order and direction,
            several curves in one stroke or one curve in several (`segment_strokes`).
        view: the orthographic camera the strokes were drawn in.
        predictor: the networks.
        renderer: a reusable MapRenderer (one is made if None).
        options: regularization, forced option, symmetry plane.
        op_type: force the operator instead of the classifier's choice (without it,
            the operators are read in the order of the classifier's probabilities, only
            those a chosen Boolean applies to when there is one (TAKE_A_BOOLEAN), until
            one reads the strokes within GOOD_FIT_PX, and the reading with the best score
            is kept: see PRIOR_PX).
    Raises:
        InterpretError: with the reason, when the sketch matches no operation.
    """
    check_sketch(strokes)
    if options.segment:  # roles and faces are read per piece of a curve, not per stroke
        strokes = segment_strokes(strokes)
    solid = solid.copy()  # rendering meshes it and fitting adds p-curves: the caller's stays
    t0 = time.perf_counter()
    ctx = to_context(solid, strokes, view, renderer or MapRenderer())
    if hasattr(predictor, "observe"):  # a structured predictor reads strokes and faces
        predictor.observe(ctx.strokes, ctx.maps.face_id)
    t1 = time.perf_counter()
    probs = np.asarray(predictor.classify(ctx.inputs), float)
    t2 = time.perf_counter()
    order = [op_type] if op_type else [LABELLED[k] for k in np.argsort(-probs, kind="stable")]
    by_rim = not classifies_the_shell(predictor, ctx)
    if by_rim:
        # a classifier of the paper's four: the shell by the strokes' geometry, read
        # first when they draw a rim, with the likeliest operator's probability
        # (`shell_prior`)
        shell = shell_prior(solid, ctx) * float(probs.max()) if op_type is None else 1.0
        if shell > 0 and op_type is None:
            order.insert(0, OperatorType.SHELL)
        probs = np.append(probs, shell)
    if options.option is not None and op_type is None:
        # a Boolean is a primitive's: a designer who chose one draws a prism or a sweep,
        # however sure the classifier is of another operator (a radial shrink of a pipe
        # draws nearly the circles of the bore drawn into it)
        order = [k for k in order if k in TAKE_A_BOOLEAN]
    weighed = _among(probs, order) if options.option is not None and op_type is None else probs
    times = {"networks": t2 - t1, "fitting": 0.0}
    read, errors = [], []
    while True:
        read_operators(solid, order, weighed, predictor, ctx, options, times, errors, read)
        if not read:
            more = (
                " (read as any other operator, the strokes did not fit either)"
                if len(errors) > 1
                else ""
            )
            if options.option is not None and op_type is None:
                more += f" (with {options.option.value} chosen, only prisms and sweeps are read)"
            if by_rim and shell > 0 and len(errors) > 1:
                # the shell, tried first, was proposed by the strokes' geometry, not read
                # by the networks: the reason given is their likeliest operator's
                errors.append(errors.pop(0))
            raise InterpretError(errors[0] + more) from None
        read.sort(key=lambda r: r[0])
        _, kind, reading = read.pop(0)
        tb = time.perf_counter()
        try:
            op, snaps, built, unsnapped = reading.op, (), reading.result, ""
            if options.regularize:
                op, snaps, built, unsnapped = _snapped(solid, reading, ctx, view, options)
            tc = time.perf_counter()
            times["fitting"] += tc - tb
            ops, result = apply_with_symmetry(solid, op, options.symmetry, built)
            left = reading.alternative
            other = left and Alternative.of(
                solid, left.op, left.result, left.fit.score, options.symmetry
            )
            break
        except (FitError, OperationError) as e:
            times["fitting"] += time.perf_counter() - tb
            errors.append(f"read as {kind.value}, but {e}")
    td = time.perf_counter()
    fit = reading.fit
    if op is not reading.op:  # snapped: scored as the reading was (`search._reading`)
        fit = (
            explained(drawn_fits(solid, op, built, ctx.camera, ctx.drawn, ctx.renderer))
            if reading.ways and ctx.renderer is not None
            else sketch_fit(solid, op, ctx.camera, ctx.strokes)
        )
    return Interpretation(
        ops,
        result,
        kind,
        # the classifier's; without its shell class, the shell's where it was proposed
        {
            c.value: float(p)
            for c, p in zip(LABELLED, probs, strict=True)
            if c is not OperatorType.SHELL or p > 0
        },
        reading.index,
        reading.labels,
        ctx.camera,
        {
            "render": 1e3 * (t1 - t0),
            "networks": 1e3 * times["networks"],
            "fitting": 1e3 * (times["fitting"] - ctx.build_s),
            "brep": 1e3 * (ctx.build_s + td - tc),
            "total": 1e3 * (td - t0),
        },
        other,
        fit,
        snaps,
        unsnapped,
        shell_by_rim=by_rim and probs[LABELLED.index(OperatorType.SHELL)] > 0,
    )
