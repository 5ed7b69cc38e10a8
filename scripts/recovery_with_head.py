# SPDX-License-Identifier: LGPL-2.1-or-later
"""End-to-end recovery with the structured head against the U-Net alone, on one data set.

    .bin/python scripts/recovery_with_head.py --data data/test-l1 --head runs/head --limit 100

interpret() does not hand the sketch's structures to its predictor yet (the hook for
inference/interpret.py is one line after `ctx = to_context(...)`:
`if hasattr(predictor, "observe"): predictor.observe(ctx.strokes, ctx.maps.face_id)`).
Until it does, this script adds that line by wrapping interpret's `to_context`, so that
the whole pipeline (render, networks, fitting, B-rep) runs with the head's F and C, and
prints the recovery rates of training/recovery.py for both predictors on the same samples.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
import torch  # noqa: E402

from Sketch2CADWorkbench.inference import interpret as interpret_module  # noqa: E402
from Sketch2CADWorkbench.inference.heads import load_structured_predictor  # noqa: E402
from Sketch2CADWorkbench.inference.weights import load_predictor  # noqa: E402
from training.heads import HEAD_NAME  # noqa: E402
from training.recovery import recovery  # noqa: E402


def observing(predictor):
    """interpret's to_context, followed by the hook that hands `predictor` the structures."""
    plain = interpret_module.to_context

    def to_context(*args, **kwargs):
        ctx = plain(*args, **kwargs)
        predictor.observe(ctx.strokes, ctx.maps.face_id)
        return ctx
    return to_context


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--data", type=Path, required=True)
    p.add_argument("--head", type=Path, required=True, help="head file or its run folder")
    p.add_argument("--weights", type=Path, help="the U-Net (default: shipped)")
    p.add_argument("--limit", type=int, default=100)
    p.add_argument("--threads", type=int, default=1)
    args = p.parse_args()
    torch.set_num_threads(args.threads)
    head = args.head / HEAD_NAME if args.head.is_dir() else args.head
    rows = {"unet": recovery(args.data, load_predictor(args.weights), args.limit)}
    structured = load_structured_predictor(head, args.weights)
    interpret_module.to_context = observing(structured)
    rows["head"] = recovery(args.data, structured, args.limit)
    ops = list(rows["unet"]["per_operator"])
    print(f"{args.data}, first {args.limit} samples: recovery strict / with the flip (%)")
    print("        " + "".join(f"{o:>16s}" for o in ops) + "   interpret ms")
    for name, r in rows.items():
        cells = "".join(f"{100 * v['recovery_rate']:7.1f} / "
                        f"{100 * v['recovery_rate_with_flip']:5.1f} "
                        if v["recovery_n"] else f"{'-':>16s}"
                        for v in r["per_operator"].values())
        print(f"{name:8s}{cells}  {r['interpret_median_ms']:.0f}")
        print(f"        n: {[v['recovery_n'] for v in r['per_operator'].values()]}; "
              f"failures: {r['failure_reasons']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
