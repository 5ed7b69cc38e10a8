# SPDX-License-Identifier: LGPL-2.1-or-later
"""Data generation throughput: `python scripts/bench_datagen.py [--count 200] [--workers 2]`.

Runs `sketch2cad datagen` into a temporary folder and prints samples per second, with
the time 40,000 samples would take at that rate. `--profile` instead generates in this
process under cProfile and lists where the time goes.
"""
from __future__ import annotations

import argparse
import cProfile
import pstats
import sys
import tempfile
import time
from pathlib import Path

from Sketch2CADWorkbench.cli import main as cli_main

TARGET = 40_000


def bench(count: int, workers: int, seed: int) -> float:
    """Samples per second of one datagen run (worker start-up included)."""
    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        rc = cli_main(["datagen", "--out", str(Path(tmp) / "set"), "--count", str(count),
                       "--seed", str(seed), "--workers", str(workers)])
        secs = time.perf_counter() - start
    if rc:
        sys.exit(rc)
    return count / secs


def profile(count: int, seed: int) -> None:
    from Sketch2CADWorkbench.datagen.generate import PER_CONTEXT, generate_block
    from Sketch2CADWorkbench.render.maps import MapRenderer
    renderer = MapRenderer()
    prof = cProfile.Profile()
    start = time.perf_counter()
    prof.enable()
    for block in range((count + PER_CONTEXT - 1) // PER_CONTEXT):
        generate_block(seed, block, 1, renderer)
    prof.disable()
    print(f"{count / (time.perf_counter() - start):.2f} samples/s in one process (profiled)")
    pstats.Stats(prof).sort_stats("tottime").print_stats(25)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--count", type=int, default=200)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--seed", type=int, default=12345)
    p.add_argument("--profile", action="store_true")
    args = p.parse_args()
    if args.profile:
        profile(args.count, args.seed)
        return
    rate = bench(args.count, args.workers, args.seed)
    print(f"bench_datagen: {rate:.2f} samples/s with {args.workers} worker(s) "
          f"({args.count} samples); {TARGET} samples would take {TARGET / rate / 60:.1f} min")


if __name__ == "__main__":
    main()
