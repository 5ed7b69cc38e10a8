# SPDX-License-Identifier: LGPL-2.1-or-later
"""Why does a step miss? Fits the first N samples of one operator in a generated set and
tallies the misses by cause.

`sketch2cad diagnose DATA OPERATOR [N] [--networks [WEIGHTS]]`: from the ground-truth
segmentation (the networks left out, as `sketch2cad eval --fitting-recovery` does), or
with `--networks` the whole pipeline from the strokes (shipped weights, or WEIGHTS, as
`sketch2cad eval --recovery` does; both through `recovery.read_step`). Prints each miss
(volume IoU < 0.95) with the true and the fitted operation, then a tally: recovered,
errors by message, and misses with the +/- option right or wrong; a wrong one is split
by whether the pipeline named the other Boolean as reading as well (the orthographic
Necker case, paper Fig. 5b) and whether that would recover it.
"""

from __future__ import annotations

import argparse
import collections
import dataclasses

from datagen.dataset import Dataset
from training.recovery import RECOVERY_IOU, read_step

from ..brep.compare import volume_iou
from ..brep.faces import OperationError
from ..brep.operators import apply_operation, replay
from ..brep.protocol import OperatorType, describe
from ..inference.context import InterpretError
from ..inference.options import InterpretOptions
from ..render.maps import MapRenderer


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("data")
    p.add_argument("operator", choices=[o.value for o in OperatorType])
    p.add_argument("n", type=int, nargs="?", default=60)
    p.add_argument(
        "--networks",
        nargs="?",
        const="",
        default=None,
        metavar="WEIGHTS",
        help="the whole pipeline with these weights (default: the shipped ones)",
    )


def run(args: argparse.Namespace) -> int:
    predictor = renderer = None
    if args.networks is not None:
        from ..inference.weights import load_predictor

        predictor, renderer = load_predictor(args.networks or None), MapRenderer()
    want = OperatorType(args.operator)
    options = InterpretOptions(regularize=False)
    tally: collections.Counter = collections.Counter()
    seen = named = 0
    ds = Dataset(args.data)
    for k in ds.shards:
        for s in ds.samples(k):
            if s.op_type is not want or seen >= args.n:
                continue
            seen += 1
            context = replay(s.context)[-1]
            truth = apply_operation(context, s.operation)
            try:
                got = read_step(s, context, predictor, renderer, options)
                op, other = got.operation, got.other_option
                iou = volume_iou(got.solid, truth)
            except (OperationError, InterpretError) as e:
                tally[f"error: {str(e)[:70]}"] += 1
                continue
            named += other is not None
            if iou >= RECOVERY_IOU:
                tally["recovered"] += 1
                continue
            if op.type is not s.op_type:
                tally[f"missed, read as {op.type.value}"] += 1
            elif getattr(op, "mode", None) == getattr(s.operation, "mode", None):
                tally["missed, option right"] += 1
            elif other is None:
                tally["missed, option wrong, no other Boolean named"] += 1
            else:
                flipped = read_step(
                    s, context, predictor, renderer, dataclasses.replace(options, option=other)
                )
                ok = volume_iou(flipped.solid, truth) >= RECOVERY_IOU
                tally[
                    f"missed, option wrong, other named, flip {'recovers' if ok else 'misses'}"
                ] += 1
            print(f"IoU {iou:.3f}\n  truth {describe(s.operation)}\n  got   {describe(op)}")
    print(
        f"{seen} {want.value} samples of {args.data} ({named} with the other Boolean "
        "named as reading as well):"
    )
    for what, count in tally.most_common():
        print(f"  {count:4d}  {what}")
    return 0
