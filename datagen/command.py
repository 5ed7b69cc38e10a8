# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad datagen`: generate a data set in parallel, deterministically, resumably.

Sample i is a function of (seed, i) alone (generate.sample_rng), so a data set is the
same whatever the number of workers. Workers make blocks of PER_CONTEXT samples (one
shared context each); the main process gathers them into shards in order and writes
each shard atomically. Shards already complete on disk are skipped, so rerunning the
same command after an interruption finishes the set.
"""
from __future__ import annotations

import argparse
import contextlib
import json
import multiprocessing as mp
import os
import sys
import time
from pathlib import Path

from tqdm import tqdm

from Sketch2CADWorkbench.render.maps import MapRenderer
from .dataset import (ARRAYS, FORMAT, VERSION, Dataset, Record, pack, shard_complete,
                      shard_name, write_shard)
from .generate import IMAGE_SIZE, PER_CONTEXT, generate_block
from .preview import write_preview

SHARD_SIZE = 256  # a multiple of PER_CONTEXT: shards hold whole blocks
NOISE_CHOICES = ["1", "2", "3", "mix"]
# Each worker runs on one thread: the workers already fill the cores, and threads of
# OpenBLAS (spinning while they wait) and of Mesa's software rasteriser would only
# compete with the other workers (measured: 25% more samples per second with 2 workers).
SINGLE_THREAD_ENV = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1",
                     "LP_NUM_THREADS": "1"}


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("datagen",
                       description="Random modeling sequences rendered as sketches over their "
                                   "context, with labels (paper, 'Training data generation').")
    p.add_argument("--out", type=Path, required=True, help="data set folder")
    p.add_argument("--count", type=int, required=True, help="number of samples")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--noise-level", default="1", choices=NOISE_CHOICES,
                   help="stroke noise: 1.4%%, 2.8%%, 4.1%% of the image diagonal (levels 1, "
                        "2, 3), or mix (the levels take turns per context); default 1")
    p.add_argument("--workers", type=int, default=2, help="processes (default 2)")
    p.add_argument("--shard-size", type=int, default=SHARD_SIZE,
                   help=f"samples per shard, a multiple of {PER_CONTEXT} (default {SHARD_SIZE})")
    p.add_argument("--preview", type=Path, help="write a contact sheet of the first samples")
    p.set_defaults(func=run)


def noise_of_block(noise: str, block: int) -> int:
    """The noise level of a block's samples."""
    return 1 + block % 3 if noise == "mix" else int(noise)


def manifest_of(args: argparse.Namespace) -> dict:
    n_shards = (args.count + args.shard_size - 1) // args.shard_size
    levels = [1, 2, 3] if args.noise_level == "mix" else [int(args.noise_level)]
    return {"format": FORMAT, "version": VERSION, "count": args.count, "seed": args.seed,
            "noise": args.noise_level, "noise_levels": levels, "image_size": IMAGE_SIZE,
            "shard_size": args.shard_size, "per_context": PER_CONTEXT, "arrays": ARRAYS,
            "shards": [f"{shard_name(k)}.npz" for k in range(n_shards)]}


# The worker's renderer: one offscreen window per process, made once.
_RENDERER: MapRenderer | None = None


def _init_worker() -> None:
    global _RENDERER
    _RENDERER = MapRenderer()


def make_block(job: tuple[int, int, str]) -> list[Record]:
    """The packed samples of block `job` = (seed, block, noise)."""
    seed, block, noise = job
    if _RENDERER is None:
        _init_worker()
    return [pack(s) for s in generate_block(seed, block, noise_of_block(noise, block),
                                            _RENDERER)]


@contextlib.contextmanager
def single_threaded_children():
    """While open, processes started from here get SINGLE_THREAD_ENV (this process's
    own libraries are loaded already and keep their settings)."""
    saved = {k: os.environ.get(k) for k in SINGLE_THREAD_ENV}
    os.environ.update(SINGLE_THREAD_ENV)
    try:
        yield
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k)
            else:
                os.environ[k] = v


def start_pool(workers: int):
    """A pool of fresh (spawned: VTK/OCCT state is not forked) single-threaded workers,
    each with its own renderer."""
    with single_threaded_children():
        return mp.get_context("spawn").Pool(workers, initializer=_init_worker)


def _error(msg: str) -> int:
    print(f"sketch2cad datagen: error: {msg}", file=sys.stderr)
    return 2


def run(args: argparse.Namespace) -> int:
    if args.count <= 0:
        return _error("--count must be positive")
    if args.shard_size <= 0 or args.shard_size % PER_CONTEXT:
        return _error(f"--shard-size must be a positive multiple of {PER_CONTEXT}")
    if args.workers <= 0:
        return _error("--workers must be positive")
    out: Path = args.out
    out.mkdir(parents=True, exist_ok=True)
    manifest = manifest_of(args)
    mpath = out / "manifest.json"
    if mpath.exists():
        old = json.loads(mpath.read_text())
        keys = ("version", "count", "seed", "noise", "shard_size")
        if {k: old.get(k) for k in keys} != {k: manifest[k] for k in keys}:
            return _error(f"{out} holds a different data set (version/count/seed/noise/shard "
                          f"size {'/'.join(str(old.get(k)) for k in keys)}); use another --out")
    mpath.write_text(json.dumps(manifest, indent=1) + "\n")

    size = args.shard_size
    todo = [k for k in range(len(manifest["shards"])) if not shard_complete(out, k)]
    counts = {k: min(size, args.count - k * size) for k in todo}
    jobs = [(args.seed, b, args.noise_level) for k in todo
            for b in range(k * size // PER_CONTEXT, (k * size + counts[k] + PER_CONTEXT - 1)
                           // PER_CONTEXT)]
    made = sum(counts.values())
    start = time.perf_counter()
    with tqdm(total=args.count, initial=args.count - made, unit="sample", desc="datagen",
              smoothing=0.05) as bar:
        if args.workers == 1:
            _collect(map(make_block, jobs), todo, counts, out, bar)
        else:
            with start_pool(args.workers) as pool:
                _collect(pool.imap(make_block, jobs), todo, counts, out, bar)
    secs = time.perf_counter() - start
    if made:
        print(f"datagen: {made} samples in {secs:.0f} s = {made / secs:.2f} samples/s with "
              f"{args.workers} worker(s); {args.count} in {out}")
    if args.preview:
        write_preview(Dataset(out), args.preview)
        print(f"datagen: preview written to {args.preview}")
    return 0


def _collect(blocks, todo: list[int], counts: dict[int, int], out: Path, bar: tqdm) -> None:
    """Gather blocks (in job order) into the shards `todo` and write each when full."""
    shards = iter(todo)
    k, records = next(shards), []
    for block in blocks:
        kept = block[:counts[k] - len(records)]  # the last shard may end inside a block
        records += kept
        bar.update(len(kept))
        if len(records) == counts[k]:
            write_shard(out, k, records)
            k, records = next(shards, None), []
