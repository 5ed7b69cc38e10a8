# SPDX-License-Identifier: LGPL-2.1-or-later
"""Classification accuracy, per-operator face IoU and curve accuracy, and latency of the
networks (paper, Table 1), and the end-to-end recovery rate of the whole pipeline.

The network figures are the U-Net's maps; when a structured head is shipped beside the
weights (the default predictor reads with it), its choices painted into F and C are
scored the same way under "structured", since they are what the fitting reads (from
the same pass of the U-Net as its own maps).

`sketch2cad eval --data DIR [--weights DIR] --json OUT.json [--report OUT.png] [--recovery N]`.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from training.evaluate import evaluate, has_ground_truth
from training.recovery import recovery
from training.report import report

from ..brep.files import write_atomically
from ..inference.options import InterpretOptions
from ..inference.weights import load_predictor, shipped_head


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--data", type=Path, required=True, help="data set folder (held out)")
    p.add_argument(
        "--weights",
        type=Path,
        help="weights file, or a run folder holding sketch2cad_net.pt "
        "(default: the weights shipped in the package)",
    )
    p.add_argument("--json", type=Path, required=True, help="write the metrics here")
    p.add_argument("--report", type=Path, help="also draw them into this PNG")
    p.add_argument("--limit", type=int, help="use the first LIMIT samples only")
    p.add_argument(
        "--latency-runs",
        type=int,
        default=50,
        help="sketches timed one by one (default %(default)s)",
    )
    p.add_argument(
        "--recovery",
        type=int,
        default=200,
        metavar="N",
        help="run the whole interpret pipeline on the first N samples for the "
        "end-to-end recovery rate (0 skips it; default %(default)s)",
    )
    p.add_argument(
        "--regularize",
        action="store_true",
        help="regularize the readings in the recovery runs (off by default)",
    )
    p.add_argument(
        "--snap-step",
        type=float,
        default=0.0,
        metavar="MM",
        help="with --regularize, round lengths to this step (default 0: no grid)",
    )
    p.add_argument(
        "--no-segment",
        action="store_true",
        help="in the recovery runs, read whole strokes without cutting and joining them "
        "into pieces of curves first (sketch/segment.py): what that stage gains",
    )
    p.add_argument(
        "--join-strokes",
        type=float,
        default=0.0,
        metavar="PX",
        help="in the recovery runs, first join each stroke to the next one starting "
        "within PX pixels of its end, at most four in one (outlines drawn in one go; "
        "default 0: as stored)",
    )
    p.add_argument(
        "--fitting-recovery",
        action="store_true",
        help="also the recovery rate of the fitting stage alone, given the "
        "ground-truth operator, F and C (tells network from fitting errors)",
    )


def run(args: argparse.Namespace) -> int:
    try:
        result, examples = evaluate(
            args.data, args.weights, args.limit, args.latency_runs, head=shipped_head(args.weights)
        )
        if args.recovery and not has_ground_truth(args.data):
            print(
                f"sketch2cad eval: warning: {args.data} stores no ground-truth operations; "
                "the end-to-end recovery is skipped",
                file=sys.stderr,
            )
        elif args.recovery:
            options = InterpretOptions(
                regularize=args.regularize, snap_step=args.snap_step, segment=not args.no_segment
            )
            rec = recovery(
                args.data,
                load_predictor(args.weights),
                args.recovery,
                options=options,
                join_px=args.join_strokes,
            )
            for op, v in rec["per_operator"].items():
                result["per_operator"][op].update(v)
            result["latency_ms"]["interpret_median"] = rec["interpret_median_ms"]
            result["operator_read_rate"] = rec["operator_read_rate"]
            result["recovery"] = {k: rec[k] for k in ("per_noise_level", "failure_reasons")}
            if args.fitting_recovery:
                fit = recovery(
                    args.data,
                    None,
                    args.recovery,
                    oracle=True,
                    options=options,
                    join_px=args.join_strokes,
                )
                for op, v in fit["per_operator"].items():
                    result["per_operator"][op]["fitting_recovery_rate"] = v["recovery_rate"]
                    result["per_operator"][op]["fitting_recovery_rate_with_flip"] = v[
                        "recovery_rate_with_flip"
                    ]
                result["fitting_recovery"] = {
                    k: fit[k] for k in ("per_noise_level", "failure_reasons")
                }
    except (FileNotFoundError, ValueError) as e:
        print(f"sketch2cad eval: error: {e}", file=sys.stderr)
        return 2
    args.json.parent.mkdir(parents=True, exist_ok=True)
    write_atomically(args.json, json.dumps(result, indent=1) + "\n")
    if args.report:
        report(result, examples, args.report)
    print(
        json.dumps(
            {
                k: result[k]
                for k in (
                    "n",
                    "classification_accuracy",
                    "operator_read_rate",
                    "per_operator",
                    "latency_ms",
                    "structured",
                )
                if k in result
            },
            indent=1,
        )
    )
    return 0
