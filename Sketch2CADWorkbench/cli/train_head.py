# SPDX-License-Identifier: LGPL-2.1-or-later
"""Train the structured heads (per-stroke roles, per-face base-face logits) on the frozen
U-Net, then score them against the U-Net's own maps on held-out data sets; rerunning with
the same --out resumes after the last finished epoch (training/heads.py).

`sketch2cad train-head --data DIR [DIR ...] --out RUN [--weights W] [--epochs N]
[--tokens CACHE] [--eval DIR ...] [--json OUT.json]`: several --data sets train on their
union (e.g. the planar set and a curved one), each set's tokens cached apart.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from training.heads import HeadSettings, evaluate_head, train_head
from training.metrics import NAMES

from ..brep.files import write_atomically
from ..inference.head.model import HeadConfig


def add_arguments(p: argparse.ArgumentParser) -> None:
    d, h = HeadSettings(), HeadConfig()
    p.add_argument(
        "--data",
        type=Path,
        nargs="+",
        required=True,
        metavar="DIR",
        help="training data sets (datagen): the head trains on their union",
    )
    p.add_argument(
        "--out",
        type=Path,
        required=True,
        help="run folder: token cache, checkpoint, sketch2cad_head.pt",
    )
    p.add_argument(
        "--tokens",
        type=Path,
        help="token cache folder (default OUT/tokens), one subfolder per data "
        "set: runs on the same data and U-Net can share one",
    )
    p.add_argument("--count", type=int, help="train on the first COUNT samples of each --data set")
    p.add_argument(
        "--weights",
        type=Path,
        help="the U-Net whose features the head reads (default: the shipped one)",
    )
    p.add_argument(
        "--init",
        type=Path,
        help="start from this head file's weights (same settings; a head of fewer "
        "classes grows, its classes keeping what they learnt)",
    )
    p.add_argument("--epochs", type=int, default=d.epochs)
    p.add_argument("--batch-size", type=int, default=d.batch_size)
    p.add_argument("--lr", type=float, default=d.lr)
    p.add_argument("--seed", type=int, default=d.seed)
    p.add_argument("--threads", type=int, default=d.threads)
    p.add_argument("--width", type=int, default=h.width)
    p.add_argument(
        "--layers",
        type=int,
        default=h.layers,
        help="attention layers (0: each token alone, no context)",
    )
    p.add_argument(
        "--no-end-bias",
        action="store_true",
        help="attention between strokes without the bias by their end gaps",
    )
    p.add_argument(
        "--eval",
        type=Path,
        nargs="*",
        default=[],
        metavar="DIR",
        help="held-out data sets to score the U-Net and the head on",
    )
    p.add_argument("--limit", type=int, help="score the first LIMIT samples of each only")
    p.add_argument("--json", type=Path, help="write the scores here")


def _row(name: str, r: dict) -> str:
    per = r["per_operator"]
    cells = " ".join(
        f"{per[k]['face_iou'] * 100:5.1f}/{per[k]['curve_accuracy'] * 100:5.1f}"
        if per[k]["n"]
        else "   -/-   "
        for k in per
    )
    return f"  {name:<6} cls {r['classification_accuracy'] * 100:6.2f}  {cells}"


def run(args: argparse.Namespace) -> int:
    try:
        settings = HeadSettings(
            epochs=args.epochs,
            batch_size=args.batch_size,
            lr=args.lr,
            seed=args.seed,
            threads=args.threads,
            init=str(args.init) if args.init else None,
            head=HeadConfig(width=args.width, layers=args.layers, end_bias=not args.no_end_bias),
        )
        final = train_head(args.data, args.out, settings, args.weights, args.tokens, args.count)
        print(f"train-head: head weights {final}")
        scores = {}
        for data in args.eval:
            r = evaluate_head(data, final, args.weights, args.limit)
            scores[str(data)] = r
            print(
                f"{data} ({r['unet']['n']} samples): face IoU / curve accuracy (%) per "
                f"operator, {' '.join(NAMES)}"
            )
            print(_row("unet", r["unet"]))
            print(_row("head", r["head"]))
        if args.json:
            args.json.parent.mkdir(parents=True, exist_ok=True)
            write_atomically(args.json, json.dumps(scores, indent=1))
    except KeyboardInterrupt:
        return 130
    except (FileNotFoundError, ValueError) as e:
        print(f"sketch2cad train-head: error: {e}", file=sys.stderr)
        return 2
    return 0
