# SPDX-License-Identifier: LGPL-2.1-or-later
"""Train the operator classifier and the segmentation networks (one shared-encoder
network); rerunning with the same --out resumes (training/train.py).

`sketch2cad train --data DIR --out DIR [--device cpu|cuda] [--minutes M | --steps N]`.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import torch

from training.train import TrainSettings, train

from ..inference.models import ModelConfig


def add_arguments(p: argparse.ArgumentParser) -> None:
    d = TrainSettings()
    p.add_argument("--data", type=Path, required=True, help="data set folder (sketch2cad datagen)")
    p.add_argument("--out", type=Path, required=True,
                   help="run folder: checkpoint, log, curves, final weights")
    p.add_argument("--device", choices=["cpu", "cuda"],
                   default="cuda" if torch.cuda.is_available() else "cpu")
    p.add_argument("--minutes", type=float, default=d.minutes,
                   help=f"wall-time budget of the training loop (default {d.minutes:g})")
    p.add_argument("--steps", type=int, default=0,
                   help="a step budget instead of --minutes (reproducible schedule)")
    p.add_argument("--batch-size", type=int, default=d.batch_size)
    p.add_argument("--lr", type=float, default=d.lr)
    p.add_argument("--threads", type=int, default=d.threads,
                   help="CPU threads for torch (default: torch's choice)")
    p.add_argument("--seed", type=int, default=d.seed)
    p.add_argument("--no-flip", action="store_true", help="no mirror-image augmentation")
    p.add_argument("--internal-size", type=int, default=d.model.internal_size,
                   help="working resolution of a new model (default %(default)s)")
    p.add_argument("--widths", type=int, nargs="+", default=list(d.model.widths),
                   help="encoder widths of a new model (default %(default)s)")


def run(args: argparse.Namespace) -> int:
    if args.device == "cuda" and not torch.cuda.is_available():
        print("sketch2cad train: error: --device cuda, but torch sees no CUDA device",
              file=sys.stderr)
        return 2
    try:
        settings = TrainSettings(
            minutes=args.minutes, steps=args.steps, batch_size=args.batch_size, lr=args.lr,
            threads=args.threads, seed=args.seed, flip=not args.no_flip, device=args.device,
            model=ModelConfig(internal_size=args.internal_size, widths=tuple(args.widths)))
        train(args.data, args.out, settings)
    except KeyboardInterrupt:
        return 130
    except (FileNotFoundError, ValueError) as e:
        print(f"sketch2cad train: error: {e}", file=sys.stderr)
        return 2
    return 0
