# SPDX-License-Identifier: LGPL-2.1-or-later
"""Why does a step miss? `python scripts/diagnose_fitting.py DATA OPERATOR [N] [--networks [W]]`

Fits the first N samples of one operator in a generated set from their ground-truth
segmentation (the networks left out, as `sketch2cad eval --fitting-recovery` does), or
with `--networks` runs the whole pipeline from the strokes (shipped weights, or those in
W, as `sketch2cad eval --recovery` does), and prints each miss (volume IoU < 0.95) with the true and the fitted operation, then a
tally: recovered, errors by message, and misses with the +/- option right or wrong
(a wrong one with both outlines on f is the orthographic Necker ambiguity).
"""
from __future__ import annotations

import argparse
import collections

from Sketch2CADWorkbench.brep.compare import volume_iou
from Sketch2CADWorkbench.brep.faces import OperationError
from Sketch2CADWorkbench.brep.operators import apply_operation, replay
from Sketch2CADWorkbench.brep.protocol import OperatorType, describe
from Sketch2CADWorkbench.datagen.dataset import Dataset
from Sketch2CADWorkbench.inference.fitting.common import FitError
from Sketch2CADWorkbench.inference.interpret import (Context, InterpretError, InterpretOptions,
                                                     fit_operation, interpret)
from Sketch2CADWorkbench.inference.recovery import RECOVERY_IOU
from Sketch2CADWorkbench.render.maps import ContextMaps, MapRenderer


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("data")
    p.add_argument("operator", choices=[o.value for o in OperatorType])
    p.add_argument("n", type=int, nargs="?", default=60)
    p.add_argument("--networks", nargs="?", const="", default=None, metavar="WEIGHTS",
                   help="the whole pipeline with these weights (default: the shipped ones)")
    args = p.parse_args()
    predictor = renderer = None
    if args.networks is not None:
        from Sketch2CADWorkbench.inference.weights import load_predictor
        predictor, renderer = load_predictor(args.networks or None), MapRenderer()
    want = OperatorType(args.operator)
    options = InterpretOptions(regularize=False)
    tally: collections.Counter = collections.Counter()
    seen = 0
    ds = Dataset(args.data)
    for k in ds.shards:
        for s in ds.samples(k):
            if s.op_type is not want or seen >= args.n:
                continue
            seen += 1
            context = replay(s.context)[-1]
            truth = apply_operation(context, s.operation)
            try:
                if predictor is not None:
                    got = interpret(context, s.strokes, s.camera, predictor, renderer, options)
                    op = got.operations[0]
                else:
                    ctx = Context(s.camera, s.strokes,
                                  ContextMaps(s.depth, s.normal, s.face_id, None), s.inputs())
                    op, _, _ = fit_operation(context, s.op_type, s.face_label, s.curve_label,
                                             ctx, options)
                iou = volume_iou(apply_operation(context, op), truth)
            except (FitError, OperationError, InterpretError) as e:
                tally[f"error: {str(e)[:70]}"] += 1
                continue
            if iou >= RECOVERY_IOU:
                tally["recovered"] += 1
                continue
            if op.type is not s.op_type:
                tally[f"missed, read as {op.type.value}"] += 1
            elif getattr(op, "mode", None) == getattr(s.operation, "mode", None):
                tally["missed, option right"] += 1
            else:
                tally["missed, option wrong"] += 1
            print(f"IoU {iou:.3f}\n  truth {describe(s.operation)}\n  got   {describe(op)}")
    print(f"{seen} {want.value} samples of {args.data}:")
    for what, count in tally.most_common():
        print(f"  {count:4d}  {what}")


if __name__ == "__main__":
    main()
