# SPDX-License-Identifier: LGPL-2.1-or-later
"""End-to-end recovery: does the whole pipeline rebuild the sketched operation?

For each sample the interpreted operation is applied to the sample's context solid and
compared with the ground truth's result: recovered when the volume IoU is >= 0.95.
The pipeline is the one the workbench runs (context frustum, render, networks, fitting,
B-rep), from the sample's raw strokes and camera. Regularization is off: the synthetic
shapes are random, so snapping them to regular ones would only move them away from the
ground truth.

A boss on f and a hole into f can draw the same lines (paper, Fig. 5b); the pipeline
then takes the addition and names the other Boolean (`Interpretation.other_option`),
which the designer picks in one click. `recovery_rate_with_flip` counts a sample as
recovered when that one click would recover it, and `other_option_share` says how
often a step offered it.
"""
from __future__ import annotations

import dataclasses
import statistics

import cadquery as cq
import numpy as np
from tqdm import tqdm

from ..brep.compare import volume_iou
from ..brep.faces import OperationError
from ..brep.operators import apply_operation, replay
from ..brep.protocol import OperatorType
from ..datagen.dataset import Dataset
from ..render.maps import ContextMaps, MapRenderer
from .fitting.common import FitError
from .interpret import (Context, InterpretError, InterpretOptions, fit_operation, interpret,
                        other_option)

RECOVERY_IOU = 0.95


def _ground_truth_step(sample, context: cq.Shape, options: InterpretOptions
                       ) -> tuple[cq.Shape, None, object]:
    """Stage three alone: fit the sample's true class, F and C in its own context maps.

    Returns:
        (result solid, None for the time, the other Boolean or None).
    """
    ctx = Context(sample.camera, sample.strokes,
                  ContextMaps(sample.depth, sample.normal, sample.face_id, None), sample.inputs())
    try:
        op, index, _ = fit_operation(context, sample.op_type, sample.face_label,
                                     sample.curve_label, ctx, options)
    except FitError as e:
        raise InterpretError(f"read as {sample.op_type.value}, but {e}") from None
    return apply_operation(context, op), None, other_option(context, op, index, ctx.camera,
                                                            options)


def recovery(data, predictor, limit: int, oracle: bool = False) -> dict:
    """Recovery rate per operator (and per noise level) over the first `limit` samples,
    and the median time of one interpret step (render + networks + fitting + B-rep).

    With `oracle`, the networks are replaced by the ground truth (class, F, C in the
    sample's own context maps): the rate then measures the fitting stage alone, which
    tells a network shortfall from a fitting one.
    """
    renderer = MapRenderer()
    ds = Dataset(data)
    hits: dict[tuple[str, int], list[bool]] = {}
    flips: dict[str, list[tuple[bool, bool]]] = {}  # (offered, recovered with the flip)
    times, reasons = [], {}
    options = InterpretOptions(regularize=False)

    def step(s, context, opts):
        if oracle:
            return _ground_truth_step(s, context, opts)
        got = interpret(context, s.strokes, s.camera, predictor, renderer, opts)
        return got.solid, got.timings_ms["total"], got.other_option

    with tqdm(total=min(limit, len(ds)), desc="fitting" if oracle else "interpret",
              unit="sample", leave=False) as bar:
        for k in ds.shards:
            for s in ds.samples(k):
                if bar.n >= limit:
                    break
                context = replay(s.context)[-1]
                other, flipped = None, False
                try:
                    truth = apply_operation(context, s.operation)
                    solid, ms, other = step(s, context, options)
                    if ms is not None:
                        times.append(ms)
                    ok = volume_iou(solid, truth) >= RECOVERY_IOU
                    if other is not None and not ok:
                        flip = dataclasses.replace(options, option=other)
                        flipped = volume_iou(step(s, context, flip)[0], truth) >= RECOVERY_IOU
                except (InterpretError, OperationError) as e:
                    ok = False
                    key = str(e).split(":")[0][:60]
                    reasons[key] = reasons.get(key, 0) + 1
                hits.setdefault((s.op_type.value, s.noise_level), []).append(ok)
                flips.setdefault(s.op_type.value, []).append((other is not None, ok or flipped))
                bar.update(1)
    per_op = {}
    for op in OperatorType:
        got = [h for (o, _), v in hits.items() if o == op.value for h in v]
        fl = flips.get(op.value, [])
        per_op[op.value] = {"recovery_rate": float(np.mean(got)) if got else None,
                            "recovery_n": len(got),
                            "recovery_rate_with_flip": float(np.mean([r for _, r in fl]))
                            if fl else None,
                            "other_option_share": float(np.mean([o for o, _ in fl]))
                            if fl else None}
    levels = sorted({lvl for _, lvl in hits})
    return {"per_operator": per_op,
            "per_noise_level": {str(lvl): {o: float(np.mean(v)) for (o, l2), v in hits.items()
                                           if l2 == lvl} for lvl in levels},
            "interpret_median_ms": float(statistics.median(times)) if times else None,
            "failure_reasons": dict(sorted(reasons.items(), key=lambda kv: -kv[1])[:10])}
