# SPDX-License-Identifier: LGPL-2.1-or-later
"""Train the operator classifier and the segmentation networks (one shared-encoder
network); rerunning with the same --out resumes (training/train.py).

`sketch2cad train --data DIR --out DIR [--device cpu|cuda] [--minutes M | --steps N]
[--nproc N]`: with --nproc, N processes on this machine under torchrun, in one
DistributedDataParallel group (training/distributed.py); on several machines run torchrun
yourself (README, "Past one machine").
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

import torch

from training import distributed
from training.train import TrainSettings, train

from ..inference.models import ModelConfig


def add_arguments(p: argparse.ArgumentParser) -> None:
    d = TrainSettings()
    p.add_argument("--data", type=Path, required=True, help="data set folder (sketch2cad datagen)")
    p.add_argument(
        "--out", type=Path, required=True, help="run folder: checkpoint, log, curves, final weights"
    )
    p.add_argument(
        "--device", choices=["cpu", "cuda"], default="cuda" if torch.cuda.is_available() else "cpu"
    )
    p.add_argument(
        "--minutes",
        type=float,
        default=d.minutes,
        help=f"wall-time budget of the training loop (default {d.minutes:g})",
    )
    p.add_argument(
        "--steps",
        type=int,
        default=0,
        help="a step budget instead of --minutes (reproducible schedule)",
    )
    p.add_argument("--batch-size", type=int, default=d.batch_size)
    p.add_argument("--lr", type=float, default=d.lr)
    p.add_argument(
        "--warmup-steps",
        type=int,
        default=d.warmup_steps,
        help="steps of linear learning-rate warmup (default %(default)s)",
    )
    p.add_argument(
        "--threads",
        type=int,
        default=d.threads,
        help="CPU threads for torch (default: torch's choice)",
    )
    p.add_argument("--seed", type=int, default=d.seed)
    p.add_argument("--no-flip", action="store_true", help="no mirror-image augmentation")
    p.add_argument(
        "--internal-size",
        type=int,
        default=d.model.internal_size,
        help="working resolution of a new model (default %(default)s)",
    )
    p.add_argument(
        "--widths",
        type=int,
        nargs="+",
        default=list(d.model.widths),
        help="encoder widths of a new model (default %(default)s)",
    )
    p.add_argument(
        "--nproc",
        type=int,
        default=1,
        help="processes on this machine (torchrun, DDP; gloo on the CPU, nccl with "
        "one GPU each); --batch-size is the global batch, --threads is split "
        "among them",
    )


def _torchrun(args: argparse.Namespace) -> int:
    """This command again in args.nproc processes under torchrun (its exit code)."""
    threads = max(1, (args.threads or os.cpu_count() or 1) // args.nproc)
    argv = [
        "--data",
        args.data,
        "--out",
        args.out,
        "--device",
        args.device,
        "--minutes",
        args.minutes,
        "--steps",
        args.steps,
        "--batch-size",
        args.batch_size,
        "--lr",
        args.lr,
        "--warmup-steps",
        args.warmup_steps,
        "--threads",
        threads,
        "--seed",
        args.seed,
        "--internal-size",
        args.internal_size,
        "--widths",
        *args.widths,
    ]
    cmd = [
        sys.executable,
        "-m",
        "torch.distributed.run",
        "--standalone",
        f"--nproc_per_node={args.nproc}",
        "-m",
        "Sketch2CADWorkbench.cli",
        "train",
        *map(str, argv),
        *(["--no-flip"] if args.no_flip else []),
    ]
    try:
        return subprocess.run(cmd).returncode
    except KeyboardInterrupt:  # torchrun passes it on; rank 0 saves a checkpoint
        return 130


def run(args: argparse.Namespace) -> int:
    if args.device == "cuda" and not torch.cuda.is_available():
        print(
            "sketch2cad train: error: --device cuda, but torch sees no CUDA device", file=sys.stderr
        )
        return 2
    if args.nproc < 1 or args.batch_size % args.nproc:
        print(
            f"sketch2cad train: error: --batch-size {args.batch_size} must be a multiple of "
            f"--nproc {args.nproc} (>= 1): each process takes an equal share",
            file=sys.stderr,
        )
        return 2
    if args.device == "cuda" and args.nproc > torch.cuda.device_count():
        print(
            f"sketch2cad train: error: --nproc {args.nproc}, but torch sees "
            f"{torch.cuda.device_count()} CUDA device(s)",
            file=sys.stderr,
        )
        return 2
    if args.nproc > 1 and "WORLD_SIZE" not in os.environ:
        return _torchrun(args)
    code = _train(args)
    if "WORLD_SIZE" in os.environ:  # a torchrun worker
        distributed.exit_worker(code)
    return code


def _train(args: argparse.Namespace) -> int:
    try:
        settings = TrainSettings(
            minutes=args.minutes,
            steps=args.steps,
            batch_size=args.batch_size,
            lr=args.lr,
            warmup_steps=args.warmup_steps,
            threads=args.threads,
            seed=args.seed,
            flip=not args.no_flip,
            device=args.device,
            model=ModelConfig(internal_size=args.internal_size, widths=tuple(args.widths)),
        )
        train(args.data, args.out, settings)
    except KeyboardInterrupt:
        return 130
    except (FileNotFoundError, ValueError) as e:
        print(f"sketch2cad train: error: {e}", file=sys.stderr)
        return 2
    return 0
