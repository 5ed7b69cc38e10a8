# SPDX-License-Identifier: LGPL-2.1-or-later
"""End-to-end recovery with the structured head against the U-Net alone, on one data set.

`sketch2cad head-recovery --data data/heldout-l1 --head runs/head --limit 200
--json runs/recovery-l1.json`: interpret() hands the sketch's strokes and face-ID map to a
predictor that has `observe` (inference/head/), so the whole pipeline (render,
networks, fitting, B-rep) runs with the head's F and C. Prints the recovery rates of
training/recovery.py for each predictor on the same samples; `--rows unet` or `--rows
head` runs one (each takes minutes per 100 samples), and `--json` keeps them, merged into
what the file already holds, so the two rows can run apart and print together.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import torch

from training.recovery import recovery

from ..inference.head.predictor import load_structured_predictor
from ..inference.weights import HEAD_NAME, load_predictor


def table(rows: dict, title: str) -> str:
    """The rows (name -> training.recovery result) as the printed table."""
    ops = list(next(iter(rows.values()))["per_operator"])
    lines = [
        f"{title}: recovery strict / with the flip (%)",
        "        " + "".join(f"{o:>16s}" for o in ops) + "   interpret ms",
    ]
    for name, r in rows.items():
        cells = "".join(
            f"{100 * v['recovery_rate']:7.1f} / {100 * v['recovery_rate_with_flip']:5.1f} "
            if v["recovery_n"]
            else f"{'-':>16s}"
            for v in r["per_operator"].values()
        )
        lines.append(f"{name:8s}{cells}  {r['interpret_median_ms']:.0f}")
        lines.append(
            f"        n: {[v['recovery_n'] for v in r['per_operator'].values()]}; "
            f"failures: {r['failure_reasons']}"
        )
    return "\n".join(lines)


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--data", type=Path, required=True, help="a generated set (datagen --out)")
    p.add_argument("--head", type=Path, help="head file or its run folder (for the head row)")
    p.add_argument("--weights", type=Path, help="the U-Net (default: shipped)")
    p.add_argument("--limit", type=int, default=100, help="samples read (the first LIMIT)")
    p.add_argument("--threads", type=int, default=1, help="torch threads")
    p.add_argument("--rows", nargs="+", choices=("unet", "head"), default=["unet", "head"])
    p.add_argument("--json", type=Path, help="keep the rows here (merged with the file's)")


def run(args: argparse.Namespace) -> int:
    if "head" in args.rows and not args.head:
        print("sketch2cad head-recovery: error: the head row needs --head", file=sys.stderr)
        return 2
    torch.set_num_threads(args.threads)
    rows = json.loads(args.json.read_text()) if args.json and args.json.exists() else {}
    for name in args.rows:
        if name == "unet":
            predictor = load_predictor(args.weights, structured=False)
        else:
            head = args.head / HEAD_NAME if args.head.is_dir() else args.head
            predictor = load_structured_predictor(head, args.weights)
        rows[name] = recovery(args.data, predictor, args.limit)
        if args.json:
            args.json.parent.mkdir(parents=True, exist_ok=True)
            args.json.write_text(json.dumps(rows, indent=1))
    print(table(rows, f"{args.data}, first {args.limit} samples"))
    return 0
