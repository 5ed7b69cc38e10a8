# SPDX-License-Identifier: LGPL-2.1-or-later
"""Data generation throughput: `python scripts/bench_datagen.py [--count 200] [--workers 2]`.

Makes `count` samples exactly as `sketch2cad datagen` does (the same worker function,
shards written to a temporary folder) and prints samples per second in the steady
state, i.e. after the worker processes have started and made one warm-up block each
(start-up takes a few seconds once per run), with the time 40,000 samples would take.
`--profile` instead generates in this process under cProfile and lists where the time
goes; `--cpu-cost` generates in this process, single-threaded, and prints the CPU
seconds per sample (this process's CPU time, so a busy machine inflates it little), with
what 400,000 samples cost in core-hours.
"""
from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import tempfile
import time
from pathlib import Path

from tqdm import tqdm

from datagen import parallel
from datagen.generate import PER_CONTEXT, generate_block
from Sketch2CADWorkbench.render.maps import MapRenderer

TARGET = 40_000
PAPER_SCALE = 400_000


def bench(count: int, workers: int, seed: int, shard_size: int = 256) -> tuple[float, float]:
    """(start-up seconds, steady samples per second) of `workers` processes."""
    blocks = (count + PER_CONTEXT - 1) // PER_CONTEXT
    jobs = [parallel.BlockJob(seed, b, "1", "draw") for b in range(blocks)]
    shards = list(range((blocks * PER_CONTEXT + shard_size - 1) // shard_size))
    counts = {k: min(shard_size, blocks * PER_CONTEXT - k * shard_size) for k in shards}
    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp, parallel.start_pool(workers) as pool:
        pool.map(parallel.make_block,
                 [parallel.BlockJob(seed + 1, b, "1", "draw") for b in range(workers)],
                 chunksize=1)
        ready = time.perf_counter()
        with tqdm(total=blocks * PER_CONTEXT, unit="sample", desc="bench") as bar:
            parallel._collect(pool.imap(parallel.make_block, jobs), shards, counts, Path(tmp), bar)
        secs = time.perf_counter() - ready
    return ready - start, blocks * PER_CONTEXT / secs


def profile(count: int, seed: int) -> None:
    renderer = MapRenderer()
    prof = cProfile.Profile()
    start = time.perf_counter()
    prof.enable()
    for block in range((count + PER_CONTEXT - 1) // PER_CONTEXT):
        generate_block(seed, block, 1, renderer)
    prof.disable()
    print(f"{count / (time.perf_counter() - start):.2f} samples/s in one process (profiled)")
    pstats.Stats(prof).sort_stats("tottime").print_stats(25)


def _cpu_seconds(count: int, seed: int) -> tuple[int, float, float]:
    """(samples, CPU s, wall s) of `count` samples in this process, after a warm-up block."""
    parallel.make_block(parallel.BlockJob(seed + 1, 0, "1", "draw"))
    blocks = (count + PER_CONTEXT - 1) // PER_CONTEXT
    cpu, wall = time.process_time(), time.perf_counter()
    for block in range(blocks):
        parallel.make_block(parallel.BlockJob(seed, block, "1", "draw"))
    return blocks * PER_CONTEXT, time.process_time() - cpu, time.perf_counter() - wall


def cpu_cost(count: int, seed: int) -> None:
    """CPU seconds per sample of one worker as datagen starts it (single-threaded)."""
    with parallel.start_pool(1) as pool:
        n, cpu, wall = pool.apply(_cpu_seconds, (count, seed))
    print(f"bench_datagen: {cpu / n * 1e3:.0f} ms CPU per sample over {n} samples in one "
          f"worker (wall {wall / n * 1e3:.0f} ms, load average {os.getloadavg()[0]:.2f} on "
          f"{os.cpu_count()} cores); {PAPER_SCALE} samples = "
          f"{PAPER_SCALE * cpu / n / 3600:.1f} core-hours")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--count", type=int, default=200)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--seed", type=int, default=12345)
    p.add_argument("--profile", action="store_true")
    p.add_argument("--cpu-cost", action="store_true")
    args = p.parse_args()
    if args.profile:
        profile(args.count, args.seed)
        return
    if args.cpu_cost:
        cpu_cost(args.count, args.seed)
        return
    startup, rate = bench(args.count, args.workers, args.seed)
    load = os.getloadavg()[0]
    print(f"bench_datagen: {rate:.2f} samples/s with {args.workers} worker(s) over "
          f"{args.count} samples (start-up {startup:.1f} s, load average {load:.2f} on "
          f"{os.cpu_count()} cores); {TARGET} samples would take "
          f"{(TARGET / rate + startup) / 60:.1f} min")


if __name__ == "__main__":
    main()
