# SPDX-License-Identifier: LGPL-2.1-or-later
"""Data generation throughput: `python benchmarks/bench_datagen.py [--count 200] [--workers 1 2]`.

Makes `count` samples exactly as `sketch2cad datagen` does (the same worker function,
shards written to a temporary folder) and prints, for each worker count, samples per
second in the steady state, i.e. after the worker processes have started and made one
warm-up block each (start-up takes a few seconds once per run), with the CPU seconds
all processes spent per sample meanwhile (robust to a busy machine, unlike the rate).
`--cpu-cost` instead makes the samples in one spawned single-threaded worker, as
datagen starts it, and writes them as shards there, and prints the CPU milliseconds per
sample of each stage (B-rep operations, tessellation, rendering, the occlusion test,
sketch synthesis, label maps, packing, compression and writing) with what 400,000
samples cost in core-hours. `--profile` generates in this process under cProfile and
lists where the time goes. `--ray` measures the same on a local Ray cluster of each
worker count, as `datagen --ray` runs it (one task per shard of `--shard-size`), after
one warm-up task per worker, and splits the CPU between the workers and Ray's own
processes (GCS, raylet, agents).
"""

from __future__ import annotations

import argparse
import collections
import cProfile
import functools
import multiprocessing as mp
import os
import pstats
import resource
import tempfile
import time
from pathlib import Path

from machine import machine_line
from tqdm import tqdm

from datagen import cluster, generate, parallel, sequences
from datagen.dataset import write_shard
from datagen.generate import PER_CONTEXT, generate_block
from Sketch2CADWorkbench.render.maps import MapRenderer

TARGET = 40_000
PAPER_SCALE = 400_000
CPU_COST_SHARD = 256  # samples per shard written by --cpu-cost, as datagen's default

# Where a worker's time goes: (namespace, function name, stage). A function is wrapped
# where its callers look it up; time in a nested stage counts to that stage alone, and
# what no stage claims counts as "other" (glue, per-sample labels).
STAGES = [
    (sequences, "operation_result", "B-rep: Booleans (apply_operation)"),
    (sequences, "sample_operation", "B-rep: faces, samplers, volumes"),
    (generate, "sample_operation", "B-rep: faces, samplers, volumes"),
    (generate, "sample_sequence", "B-rep: faces, samplers, volumes"),
    (generate, "operation_curves", "B-rep: sketch curves, face index"),
    (generate, "base_face_index", "B-rep: sketch curves, face index"),
    (generate, "tessellate", "tessellation"),
    (generate, "view_direction", "views (direction, framing)"),
    (generate, "up_vector", "views (direction, framing)"),
    (generate, "frame_curves", "views (direction, framing)"),
    (MapRenderer, "triangle_ids", "render: VTK draw, read-back"),
    (MapRenderer, "render", "render: maps from triangle IDs"),
    (generate, "is_informative", "occlusion test"),
    (generate, "shows_base_face", "occlusion test"),
    (generate, "visible_curves", "occlusion test"),
    (generate, "sketch_strokes", "sketch synthesis (strokes, noise)"),
    (generate, "stroke_maps", "stroke and label maps"),
    (parallel, "pack", "packing"),
]
WRITING = "compression, writing"


class StageClock:
    """CPU seconds (this process, all threads) per stage, exclusive of nested stages."""

    def __init__(self):
        self.seconds: collections.Counter[str] = collections.Counter()
        self._stack = ["other"]
        self._since = time.process_time()

    def _switch(self, push: str | None) -> None:
        now = time.process_time()
        self.seconds[self._stack[-1]] += now - self._since
        self._since = now
        if push is None:
            self._stack.pop()
        else:
            self._stack.append(push)

    def wrap(self, fn, stage: str):
        @functools.wraps(fn)
        def timed(*args, **kwargs):
            self._switch(stage)
            try:
                return fn(*args, **kwargs)
            finally:
                self._switch(None)

        return timed


def bench(
    count: int, workers: int, seed: int, shard_size: int = 256
) -> tuple[float, float, float, float]:
    """(start-up seconds, steady samples per second, steady CPU seconds per sample of
    the workers and this process together, and of this process alone: it receives the
    blocks and writes the shards) of `workers` processes, as datagen runs them.

    The steady state starts once the first `workers` blocks, one warm-up block per
    worker of another seed, are back."""
    blocks = (count + PER_CONTEXT - 1) // PER_CONTEXT
    warmup = [parallel.BlockJob(seed + 1, b, "1", "draw") for b in range(workers)]
    jobs = [parallel.BlockJob(seed, b, "1", "draw") for b in range(blocks)]
    shards = list(range((blocks * PER_CONTEXT + shard_size - 1) // shard_size))
    counts = {k: min(shard_size, blocks * PER_CONTEXT - k * shard_size) for k in shards}
    start = time.perf_counter()
    made = parallel.made_in_pool(parallel.make_block, warmup + jobs, workers)
    for _ in warmup:
        next(made)
    ready = time.perf_counter()
    # The workers' CPU so far, read live; once they have exited, the kernel books their
    # whole CPU to this process's children.
    before = _live_children_cpu() + _exited_children_cpu()
    main = time.process_time()
    with (
        tempfile.TemporaryDirectory() as tmp,
        tqdm(total=blocks * PER_CONTEXT, unit="sample", desc="bench") as bar,
    ):
        parallel._collect(made, shards, counts, Path(tmp), bar)
    secs = time.perf_counter() - ready
    main = time.process_time() - main
    children = _exited_children_cpu() - before
    n = blocks * PER_CONTEXT
    return ready - start, n / secs, (children + main) / n, main / n


def bench_ray(
    count: int, workers: int, seed: int, shard_size: int
) -> tuple[float, float, float, float]:
    """(start-up seconds, steady samples per second, steady CPU seconds per sample of
    the Ray workers, and of Ray's own processes) of a local Ray cluster of `workers`
    CPUs making `count` samples in shard tasks of `shard_size`, written to a temporary
    folder. The steady state starts once one warm-up task per worker (one block of
    another seed) is back."""
    start = time.perf_counter()
    with cluster.ray_cluster("local", workers) as ray, tempfile.TemporaryDirectory() as tmp:
        warm = parallel.DatagenSettings(
            Path(tmp) / "warm", workers * PER_CONTEXT, seed + 1, shard_size=PER_CONTEXT
        )
        timed = parallel.DatagenSettings(Path(tmp) / "set", count, seed, shard_size=shard_size)
        for settings in (warm, timed):
            settings.out.mkdir()
        cluster.make_shards(
            ray, warm, {k: PER_CONTEXT for k in range(workers)}, tqdm(disable=True), lambda k: None
        )
        ready = time.perf_counter()
        before = _ray_cpu()
        counts = {
            k: min(shard_size, count - k * shard_size)
            for k in range((count + shard_size - 1) // shard_size)
        }
        with tqdm(total=count, unit="sample", desc="bench") as bar:
            failed = cluster.make_shards(ray, timed, counts, bar, lambda k: None)
        secs = time.perf_counter() - ready
        after = _ray_cpu()
    if failed:
        raise RuntimeError("; ".join(failed))
    return (
        ready - start,
        count / secs,
        (after[0] - before[0]) / count,
        (after[1] - before[1]) / count,
    )


def _ray_cpu() -> tuple[float, float]:
    """User + system CPU seconds of the live Ray workers among this process's
    descendants (their titles start "ray::"), and of the other descendants: the local
    cluster's own processes (Linux /proc)."""
    stats = {}
    for pid in (int(p) for p in os.listdir("/proc") if p.isdigit()):
        try:
            stats[pid] = (
                *_proc_stat(pid),
                Path(f"/proc/{pid}/cmdline").read_bytes().startswith(b"ray::"),
            )
        except OSError:  # exited meanwhile
            continue
    mine, grew = {os.getpid()}, True
    while grew:
        new = {pid for pid, (ppid, _, _) in stats.items() if ppid in mine} - mine
        mine |= new
        grew = bool(new)
    mine.discard(os.getpid())
    workers = sum(stats[p][1] for p in mine if stats[p][2])
    return workers, sum(stats[p][1] for p in mine) - workers


def _live_children_cpu() -> float:
    """User + system CPU seconds of this process's live children (Linux /proc)."""
    return sum(_proc_stat(child.pid)[1] for child in mp.active_children())


def _proc_stat(pid: int) -> tuple[int, float]:
    """(parent pid, user + system CPU seconds) of a live process (Linux /proc/PID/stat;
    OSError once it has exited)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return int(fields[1]), (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _exited_children_cpu() -> float:
    """User + system CPU seconds of this process's children that have exited."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


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


def _stage_seconds(job: tuple[int, int]) -> tuple[int, dict[str, float], float, float]:
    """(samples, CPU s per stage, CPU s, wall s) of job = (count, seed): `count` samples
    made and written in shards in this process, after a warm-up block."""
    count, seed = job
    parallel.make_block(parallel.BlockJob(seed + 1, 0, "1", "draw"))
    clock = StageClock()
    for owner, name, stage in STAGES:
        setattr(owner, name, clock.wrap(getattr(owner, name), stage))
    write = clock.wrap(write_shard, WRITING)
    blocks = (count + PER_CONTEXT - 1) // PER_CONTEXT
    cpu, wall = time.process_time(), time.perf_counter()
    clock.seconds.clear()
    clock._since = cpu
    records = []
    with tempfile.TemporaryDirectory() as tmp:
        for block in range(blocks):
            records += parallel.make_block(parallel.BlockJob(seed, block, "1", "draw"))
            if len(records) >= CPU_COST_SHARD or block == blocks - 1:
                write(Path(tmp), block, records)
                records = []
        clock._switch("other")  # books the time since the last stage
    return (
        blocks * PER_CONTEXT,
        dict(clock.seconds),
        time.process_time() - cpu,
        time.perf_counter() - wall,
    )


def cpu_cost(count: int, seed: int) -> None:
    """CPU seconds per sample, by stage, of one worker as datagen starts it
    (single-threaded), writing its own shards."""
    n, stages, cpu, wall = next(parallel.made_in_pool(_stage_seconds, [(count, seed)], 1))
    for stage, secs in sorted(stages.items(), key=lambda kv: -kv[1]):
        print(f"  {stage:36s} {secs / n * 1e3:7.1f} ms  {100 * secs / cpu:5.1f}%")
    print(
        f"bench_datagen: {cpu / n * 1e3:.1f} ms CPU per sample over {n} samples in one "
        f"worker (wall {wall / n * 1e3:.0f} ms, load average {os.getloadavg()[0]:.2f} on "
        f"{os.cpu_count()} cores); {PAPER_SCALE} samples = "
        f"{PAPER_SCALE * cpu / n / 3600:.1f} core-hours"
    )


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--count", type=int, default=200)
    p.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    p.add_argument("--seed", type=int, default=12345)
    p.add_argument("--profile", action="store_true")
    p.add_argument("--cpu-cost", action="store_true")
    p.add_argument("--ray", action="store_true", help="on a local Ray cluster")
    p.add_argument("--shard-size", type=int, default=64, help="samples per Ray task")
    args = p.parse_args()
    print(machine_line())
    if args.profile:
        profile(args.count, args.seed)
        return
    if args.cpu_cost:
        cpu_cost(args.count, args.seed)
        return
    if args.ray:
        rates = []
        for workers in args.workers:
            load = os.getloadavg()[0]
            startup, rate, cpu, own = bench_ray(args.count, workers, args.seed, args.shard_size)
            rates.append(rate)
            print(
                f"bench_datagen: Ray, {rate:.2f} samples/s with {workers} worker(s) over "
                f"{args.count} samples in tasks of {args.shard_size}, {cpu * 1e3:.1f} ms "
                f"CPU per sample in the workers and {own * 1e3:.1f} ms in Ray's own "
                f"processes (start-up {startup:.1f} s, load average {load:.2f} -> "
                f"{os.getloadavg()[0]:.2f} on {os.cpu_count()} cores)"
            )
        if len(rates) > 1:
            print(
                f"bench_datagen: Ray, {rates[-1] / rates[0]:.2f}x from {args.workers[0]} to "
                f"{args.workers[-1]} workers"
            )
        return
    for workers in args.workers:
        load = os.getloadavg()[0]
        startup, rate, cpu, main_cpu = bench(args.count, workers, args.seed)
        print(
            f"bench_datagen: {rate:.2f} samples/s with {workers} worker(s) over "
            f"{args.count} samples, {cpu * 1e3:.1f} ms CPU per sample in all processes, "
            f"{main_cpu * 1e3:.1f} ms of it in the writing main process (start-up "
            f"{startup:.1f} s, load average {load:.2f} -> "
            f"{os.getloadavg()[0]:.2f} on {os.cpu_count()} cores); {TARGET} samples would "
            f"take {(TARGET / rate + startup) / 60:.1f} min"
        )


if __name__ == "__main__":
    main()
