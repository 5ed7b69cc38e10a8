# SPDX-License-Identifier: LGPL-2.1-or-later
"""End-to-end recovery: does the whole pipeline rebuild the sketched operation?

For each sample the interpreted operation is applied to the sample's context solid and
compared with the ground truth's result: recovered when the volume IoU is >= 0.95.
The pipeline is the one the workbench runs (context frustum, render, networks, fitting,
B-rep), from the sample's raw strokes and camera. Regularization is off unless asked
(`options`): the synthetic shapes are random, and it should not move them away from the
ground truth (the strokes' camera is the view its pixel tolerance is measured in).

A boss on f and a hole into f can draw the same lines (paper, Fig. 5b); the pipeline
then takes the addition and names the other Boolean (`Interpretation.other_option`),
which the designer picks in one click. `recovery_rate_with_flip` counts a sample as
recovered when that one click would recover it, and `other_option_share` says how
often a step offered it. `strict_ceiling` is the most a strict reading by the +/- rule
can reach: the share of samples whose other Boolean does not draw the same lines so that
the pipeline's +/- rule, given the operation's own outlines, takes it (a hole read as the
boss on its rim, the paper's default; a boss overhanging f read as the hole its far
outline rims). Other cues (a reading that builds nothing) can beat it.
`strokes_ceiling` is the most a reading chosen by how well its own sketch explains the
strokes can reach on these samples: the share of samples not missed by a reading that
explains them better than the truth does (`SketchFit.score`, the score readings are
ranked by), where the hand drew the reading more than the truth.
"""

from __future__ import annotations

import dataclasses
import statistics
from dataclasses import dataclass

import cadquery as cq
import numpy as np
from tqdm import tqdm

from datagen.dataset import Dataset
from datagen.hand import join_end_to_start
from Sketch2CADWorkbench.brep.compare import volume_iou
from Sketch2CADWorkbench.brep.faces import OperationError, resolve_face
from Sketch2CADWorkbench.brep.operators import apply_operation, replay
from Sketch2CADWorkbench.brep.protocol import AddSubPrism, Mode, Operation, OperatorType, Sweep
from Sketch2CADWorkbench.inference.context import Context, InterpretError
from Sketch2CADWorkbench.inference.fitting.common import FitError, resample
from Sketch2CADWorkbench.inference.fitting.primitive import choose_option
from Sketch2CADWorkbench.inference.fitting.surface import face_frame
from Sketch2CADWorkbench.inference.fitting.verify import sketch_fit
from Sketch2CADWorkbench.inference.interpret import interpret, snap_or_keep
from Sketch2CADWorkbench.inference.options import InterpretOptions
from Sketch2CADWorkbench.inference.search import TAKE_A_BOOLEAN, read_operation
from Sketch2CADWorkbench.render.maps import ContextMaps, MapRenderer
from Sketch2CADWorkbench.sketch.curves import operation_curves
from Sketch2CADWorkbench.sketch.labels import END, START
from Sketch2CADWorkbench.sketch.segment import segment_strokes

RECOVERY_IOU = 0.95


@dataclass
class StepReading:
    """How one sample's sketch step was read."""

    operation: Operation
    solid: cq.Shape  # the sample's context solid with the operation applied
    other_option: Mode | None  # the other Boolean, when named as reading as well
    interpret_ms: float | None  # the whole step's time; None for the fitting stage alone


def read_step(
    sample, context: cq.Shape, predictor, renderer: MapRenderer | None, options: InterpretOptions
) -> StepReading:
    """Read one sample's step: by the whole pipeline with `predictor`, or with None by
    the fitting stage alone, given the sample's true class, F and C in its own context
    maps (and the strokes cut and joined into curves first, as interpret does, unless
    `options.segment` is off).

    Raises:
        InterpretError: the strokes do not fit; OperationError: the result does not build.
    """
    if predictor is not None:
        got = interpret(context, sample.strokes, sample.camera, predictor, renderer, options)
        return StepReading(got.operations[0], got.solid, got.other_option, got.timings_ms["total"])
    ctx = Context(
        sample.camera,
        segment_strokes(sample.strokes) if options.segment else sample.strokes,
        ContextMaps(sample.depth, sample.normal, sample.face_id, view_depth=None),
        sample.inputs(),
        renderer=renderer,
    )
    try:
        reading = read_operation(
            context, sample.op_type, sample.face_label, sample.curve_label, ctx, options
        )
    except FitError as e:
        raise InterpretError(f"read as {sample.op_type.value}, but {e}") from None
    op, index = reading.op, reading.index
    result = None
    if options.regularize:  # as interpret() does after fitting
        op, _, result, _ = snap_or_keep(
            context,
            op,
            context.Faces()[index],
            lambda moved: ctx.sketch_fit(context, moved),
            ctx.camera,
            sample.camera,
            options,
        )
    return StepReading(
        op,
        apply_operation(context, op) if result is None else result,
        alternative.op.mode
        if (alternative := reading.alternative) and isinstance(alternative.op, (AddSubPrism, Sweep))
        else None,
        None,
    )


def the_other_boolean_draws_it(context: cq.Shape, sample) -> bool:
    """Whether the sample is an addition or subtraction (prism or sweep) that the
    pipeline's +/- rule (`choose_option`, on the operation's own outlines as perfect
    strokes) reads as the other Boolean drawing the same lines (paper, Fig. 5b): a hole
    whose boss stands on its rim (the rule's default is the boss), or a boss overhanging
    f whose far outline lies on f (the hole with that rim). No strict reading by the rule
    recovers it."""
    op = sample.operation
    if op.type not in TAKE_A_BOOLEAN or op.mode.flipped is None:
        return False
    cam = sample.camera
    curves = operation_curves(context, op, np.asarray(cam.direction, float))
    start, end = (
        np.concatenate([resample(cam.project(c.points)[0], 2.0) for c in curves if c.label == k])
        for k in (START, END)
    )
    face = resolve_face(context, op.face).face
    try:
        return (
            choose_option(
                face, face_frame(face, cam, np.concatenate([start, end])), cam, start, end, None
            )
            is op.mode.flipped
        )
    except FitError:
        return False


def strokes_favour(context: cq.Shape, reading: Operation, sample) -> bool:
    """Whether the reading's own sketch explains the sample's strokes better than the
    true operation's (`SketchFit.score`, both reprojected in the sample's camera):
    a miss the strokes favour."""

    def score(op: Operation) -> float:
        return sketch_fit(context, op, sample.camera, sample.strokes).score

    return score(reading) < score(sample.operation)


def recovery(
    data,
    predictor,
    limit: int,
    oracle: bool = False,
    options: InterpretOptions = InterpretOptions(regularize=False),
    join_px: float = 0.0,
) -> dict:
    """Recovery rate and mean and median volume IoU per operator (and the rate per noise
    level) over the first `limit` samples, and the median time of one interpret step
    (render + networks + fitting + B-rep). The IoU is the reading's, before any flip; a
    sketch that is not read, or whose reading does not build, counts 0. The median shows
    how exact a typical reading is, which the rate (a threshold) does not. Also the share
    of the samples, per operator and over all, whose reading is of the operator drawn
    (five classes: the shell too, which a classifier of four leaves to its rim); a
    sketch that is not read counts as read otherwise.

    With `oracle`, the networks are replaced by the ground truth (class, F, C in the
    sample's own context maps): the rate then measures the fitting stage alone, which
    tells a network shortfall from a fitting one. `options`: regularization (off by
    default) and its grid step. With `join_px`, each sample's strokes are first joined
    end to start within that many pixels (`hand.join_end_to_start`: outlines drawn in
    one go).
    """
    renderer = MapRenderer()
    ds = Dataset(data)
    hits: dict[tuple[str, int], list[bool]] = {}
    flips: dict[str, list[tuple[bool, bool]]] = {}  # (offered, recovered with the flip)
    beyond: dict[str, list[bool]] = {}  # a hole a boss draws: beyond a strict reading
    favoured: dict[str, list[bool]] = {}  # missed by a reading nearer the strokes than truth
    ious: dict[str, list[float]] = {}
    read_as: dict[str, list[bool]] = {}  # read as the operator drawn, right or not
    times, reasons = [], {}
    reader = None if oracle else predictor

    with tqdm(
        total=min(limit, len(ds)),
        desc="fitting" if oracle else "interpret",
        unit="sample",
        leave=False,
    ) as bar:
        for k in ds.shards:
            for s in ds.samples(k):
                if bar.n >= limit:
                    break
                context = replay(s.context)[-1]
                if join_px:
                    s = dataclasses.replace(s, strokes=join_end_to_start(s.strokes, join_px))
                other, flipped, iou, nearer, same = None, False, 0.0, False, False
                try:
                    truth = apply_operation(context, s.operation)
                    got = read_step(s, context, reader, renderer, options)
                    same = got.operation.type is s.op_type
                    other = got.other_option
                    if got.interpret_ms is not None:
                        times.append(got.interpret_ms)
                    iou = volume_iou(got.solid, truth)
                    ok = iou >= RECOVERY_IOU
                    if other is not None and not ok:
                        flip = dataclasses.replace(options, option=other)
                        flipped = (
                            volume_iou(read_step(s, context, reader, renderer, flip).solid, truth)
                            >= RECOVERY_IOU
                        )
                    if not ok:
                        nearer = strokes_favour(context, got.operation, s)
                except (InterpretError, OperationError) as e:
                    ok = False
                    key = str(e).split(":")[0][:60]
                    reasons[key] = reasons.get(key, 0) + 1
                hits.setdefault((s.op_type.value, s.noise_level), []).append(ok)
                beyond.setdefault(s.op_type.value, []).append(
                    the_other_boolean_draws_it(context, s)
                )
                favoured.setdefault(s.op_type.value, []).append(nearer)
                flips.setdefault(s.op_type.value, []).append((other is not None, ok or flipped))
                ious.setdefault(s.op_type.value, []).append(iou)
                read_as.setdefault(s.op_type.value, []).append(same)
                bar.update(1)
    per_op = {}
    for op in OperatorType:
        got = [h for (o, _), v in hits.items() if o == op.value for h in v]
        fl = flips.get(op.value, [])
        per_op[op.value] = {
            "recovery_rate": float(np.mean(got)) if got else None,
            "recovery_n": len(got),
            "mean_iou": float(np.mean(ious[op.value])) if got else None,
            "median_iou": float(np.median(ious[op.value])) if got else None,
            "recovery_rate_with_flip": float(np.mean([r for _, r in fl])) if fl else None,
            "other_option_share": float(np.mean([o for o, _ in fl])) if fl else None,
            "strict_ceiling": 1.0 - float(np.mean(beyond[op.value]))
            if beyond.get(op.value)
            else None,
            "strokes_ceiling": 1.0 - float(np.mean(favoured[op.value]))
            if favoured.get(op.value)
            else None,
            # the pipeline's own reading of the operator, the shell included where its
            # rim proposes it (the oracle is given the class: None)
            "read_as_rate": float(np.mean(read_as[op.value]))
            if read_as.get(op.value) and not oracle
            else None,
        }
    everything = [r for v in read_as.values() for r in v]
    levels = sorted({lvl for _, lvl in hits})
    return {
        "per_operator": per_op,
        "per_noise_level": {
            str(lvl): {o: float(np.mean(v)) for (o, l2), v in hits.items() if l2 == lvl}
            for lvl in levels
        },
        "interpret_median_ms": float(statistics.median(times)) if times else None,
        "operator_read_rate": float(np.mean(everything)) if everything and not oracle else None,
        "failure_reasons": dict(sorted(reasons.items(), key=lambda kv: -kv[1])[:10]),
    }
