# SPDX-License-Identifier: LGPL-2.1-or-later
"""Generating a data set in parallel, deterministically, resumably (`sketch2cad datagen`).

Sample i is a function of (seed, i) alone (generate.sample_rng), so a data set is the
same whatever the number of workers. Workers make blocks of PER_CONTEXT samples (one
shared context each); the main process gathers them into shards in order and writes
each shard atomically. Shards already complete on disk are skipped, so rerunning the
same command after an interruption finishes the set. A pool worker that dies (killed,
out of memory) is replaced once without losing work (`made_in_pool`). With `--ray`, each
shard is one task of a Ray cluster instead (cluster.py), made by `make_shard` from
(seed, shard index) alone: the same bytes.
"""

from __future__ import annotations

import collections
import contextlib
import json
import multiprocessing as mp
import os
import sys
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from pathlib import Path
from typing import TypeVar

from tqdm import tqdm

from Sketch2CADWorkbench.brep.files import atomic_path
from Sketch2CADWorkbench.render.maps import MapRenderer

from .dataset import (
    ARRAYS,
    FORMAT,
    VERSION,
    Dataset,
    Record,
    pack,
    shard_complete,
    shard_name,
    write_shard,
)
from .generate import IMAGE_SIZE, PER_CONTEXT, generate_block
from .hand import HANDS
from .preview import write_preview

SHARD_SIZE = 256  # a multiple of PER_CONTEXT: shards hold whole blocks
NOISE_CHOICES = ["1", "2", "3", "mix"]
# Hidden lines: drawn (the paper's sketches), left out as a designer drawing only what
# is seen does (sketch/visible.py), or the two taking turns per context block.
HIDDEN_CHOICES = ["draw", "omit", "mix"]
# Each worker runs on one thread: the workers already fill the cores, and threads of
# OpenBLAS (spinning while they wait) and of Mesa's software rasteriser would only
# compete with the other workers (docs/measurements.md, parallel.SINGLE_THREAD_ENV).
SINGLE_THREAD_ENV = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "LP_NUM_THREADS": "1"}


@dataclass
class DatagenSettings:
    """What `generate_dataset` makes (the `sketch2cad datagen` options)."""

    out: Path
    count: int
    seed: int = 0
    noise_level: str = "1"  # one of NOISE_CHOICES
    hidden_lines: str = "draw"  # one of HIDDEN_CHOICES
    workers: int = 2
    shard_size: int = SHARD_SIZE  # a multiple of PER_CONTEXT
    preview: Path | None = None  # also write a contact sheet of the first samples
    ray: str | None = None  # a Ray cluster's address ("local": start one of
    # `workers` CPUs here); None: a process pool
    regular_share: float = 0.0  # share of operations drawn regular (datagen/regular.py)
    hand: str = "generator"  # one of hand.HANDS: who draws the strokes
    shells: bool = False  # last operations may be shells (generate.last_op_weights)
    round_share: float = 0.0  # share of last bevels drawn across an edge (datagen/rounds.py)


@dataclass(frozen=True)
class BlockJob:
    """One block of samples to make (`make_block`): which, and how they are drawn."""

    seed: int
    block: int
    noise: str  # one of NOISE_CHOICES
    hidden: str  # one of HIDDEN_CHOICES
    regular_share: float = 0.0
    hand: str = "generator"  # one of hand.HANDS
    shells: bool = False
    round_share: float = 0.0


def noise_of_block(noise: str, block: int) -> int:
    """The noise level of a block's samples."""
    return 1 + block % 3 if noise == "mix" else int(noise)


def hidden_lines_of_block(hidden: str, block: int) -> bool:
    """Whether a block's samples draw the hidden lines."""
    return hidden == "draw" or (hidden == "mix" and block % 2 == 0)


def manifest_of(settings: DatagenSettings, complete: list[int]) -> dict:
    """The manifest; "complete" lists the shards written so far (all, once finished)."""
    n_shards = (settings.count + settings.shard_size - 1) // settings.shard_size
    levels = [1, 2, 3] if settings.noise_level == "mix" else [int(settings.noise_level)]
    # written only when used: a set made without rounds keeps the manifest it had
    rounds = {"round_share": settings.round_share} if settings.round_share else {}
    return {
        "format": FORMAT,
        "version": VERSION,
        "count": settings.count,
        "seed": settings.seed,
        "noise": settings.noise_level,
        "noise_levels": levels,
        "hidden_lines": settings.hidden_lines,
        "regular_share": settings.regular_share,
        "hand": settings.hand,
        **({"shells": True} if settings.shells else {}),  # sets without: as before
        **rounds,
        "image_size": IMAGE_SIZE,
        "shard_size": settings.shard_size,
        "per_context": PER_CONTEXT,
        "arrays": ARRAYS,
        "shards": [f"{shard_name(k)}.npz" for k in range(n_shards)],
        "complete": sorted(complete),
    }


def shard_jobs(
    seed: int,
    noise: str,
    hidden: str,
    k: int,
    count: int,
    shard_size: int,
    regular_share: float = 0.0,
    hand: str = "generator",
    shells: bool = False,
    round_share: float = 0.0,
) -> list[BlockJob]:
    """The blocks (make_block's jobs) of shard k, which holds `count` samples."""
    first = k * shard_size // PER_CONTEXT
    return [
        BlockJob(seed, b, noise, hidden, regular_share, hand, shells, round_share)
        for b in range(first, first + (count + PER_CONTEXT - 1) // PER_CONTEXT)
    ]


# The worker's renderer: one offscreen window per process, made once.
_RENDERER: MapRenderer | None = None


def _init_worker() -> None:
    global _RENDERER
    _RENDERER = MapRenderer()


def _init_pool_worker(parent: int) -> None:
    """A pool worker's start: its renderer, and a watch that ends it when the main
    process `parent` is gone (killed: its queue's pipe stays open in the workers, so they
    would wait on it for ever, holding hundreds of MB and multiprocessing's resource
    tracker), even if that happened while the worker was still importing."""

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(PARENT_POLL_S)
        os._exit(1)

    threading.Thread(target=watch, name="exit-with-the-main-process", daemon=True).start()
    _init_worker()


def make_block(job: BlockJob) -> list[Record]:
    """The packed samples of block `job`."""
    if _RENDERER is None:
        _init_worker()
    b = job.block
    return [
        pack(s)
        for s in generate_block(
            job.seed,
            b,
            noise_of_block(job.noise, b),
            _RENDERER,
            hidden_lines=hidden_lines_of_block(job.hidden, b),
            regular_share=job.regular_share,
            hand=job.hand,
            shells=job.shells,
            round_share=job.round_share,
        )
    ]


def make_shard(
    out: str,
    seed: int,
    noise: str,
    hidden: str,
    k: int,
    count: int,
    shard_size: int,
    regular_share: float = 0.0,
    hand: str = "generator",
    shells: bool = False,
    round_share: float = 0.0,
) -> int:
    """Make and write shard k of data set `seed` (count samples; the unit of work of a
    cluster); returns k. The same bytes as the process pool writes."""
    records = [
        r
        for job in shard_jobs(
            seed, noise, hidden, k, count, shard_size, regular_share, hand, shells, round_share
        )
        for r in make_block(job)
    ]
    write_shard(Path(out), k, records[:count])
    return k


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


class WorkerDied(RuntimeError):
    """A pool's worker process died (killed, out of memory, or crashed in a native
    library) again after the pool was started afresh once."""


J = TypeVar("J")
R = TypeVar("R")
# Blocks queued per worker ahead of the one the main process waits for: enough to keep
# every core busy while a slow block holds up the order, and a bound on the results held
# in memory however large the set.
LOOK_AHEAD = 4
# How often a pool worker looks whether the main process is still there (seconds).
PARENT_POLL_S = 0.5


def made_in_pool(make: Callable[[J], R], jobs: Sequence[J], workers: int) -> Iterator[R]:
    """make(job) for each of `jobs`, in their order, computed by `workers` fresh
    (spawned: VTK/OCCT state is not forked) single-threaded processes, each with its own
    renderer.

    At most LOOK_AHEAD * workers jobs are queued or done ahead of the one yielded next.
    A worker that dies takes its pool down with it; the jobs not yet yielded then run in
    a fresh pool (a block is a function of its job alone, so the output is the same),
    once: a second death raises WorkerDied, since a crash that repeats is not bad luck.

    Raises:
        WorkerDied: saying which job was awaited when a worker died the second time.
    """
    yielded = 0
    for attempt in (1, 2):
        pool = ProcessPoolExecutor(
            workers, mp.get_context("spawn"), initializer=_init_pool_worker, initargs=(os.getpid(),)
        )
        try:
            with single_threaded_children():  # the first jobs queued spawn all workers
                queued = collections.deque(
                    pool.submit(make, job) for job in jobs[yielded : yielded + LOOK_AHEAD * workers]
                )
            while queued:
                result = queued.popleft().result()
                following = yielded + len(queued) + 1
                if following < len(jobs):
                    queued.append(pool.submit(make, jobs[following]))
                yielded += 1
                yield result
            return
        except BrokenProcessPool:
            if attempt == 2:
                raise WorkerDied(
                    f"a worker process died twice, the second time while job "
                    f"{yielded + 1} of {len(jobs)} was awaited (killed, out "
                    f"of memory, or crashed in VTK/OCCT: --workers 1 shows "
                    f"the crash)"
                ) from None
        finally:
            pool.shutdown(wait=True, cancel_futures=True)


@dataclass
class SetFolder:
    """A data set's folder made shard by shard: the shards complete so far, and the
    manifest (manifest_of, plus `extra` entries such as a curved set's) rewritten
    atomically as each shard is added, so that a rerun makes only the rest."""

    settings: DatagenSettings
    extra: dict
    complete: list[int]

    def done(self, k: int | None) -> None:
        """Record shard k as written (None: only write the manifest)."""
        if k is not None:
            self.complete.append(k)
        with atomic_path(self.settings.out / "manifest.json") as tmp:
            tmp.write_text(
                json.dumps({**manifest_of(self.settings, self.complete), **self.extra}, indent=1)
                + "\n"
            )


def open_set_folder(settings: DatagenSettings, extra: dict | None = None) -> SetFolder | str:
    """The folder settings.out, made if missing, with the shards already complete there;
    or why it cannot take this data set (it holds another one: a different version,
    count, seed, noise, shard size, hidden lines, regular share or `extra`)."""
    out, extra = settings.out, extra or {}
    out.mkdir(parents=True, exist_ok=True)
    manifest = {**manifest_of(settings, []), **extra}
    mpath = out / "manifest.json"
    if mpath.exists():
        old = json.loads(mpath.read_text())
        keys = (
            "version",
            "count",
            "seed",
            "noise",
            "shard_size",
            "hidden_lines",
            "regular_share",
            "hand",
            "shells",
            "round_share",
            *tuple(extra),
        )
        old.setdefault("hidden_lines", "draw")  # sets made before the choice drew them
        old.setdefault("regular_share", 0.0)  # ... and before regular samples
        old.setdefault("hand", "generator")  # ... and before people's hand
        old.setdefault("round_share", 0.0)  # ... and sets without rounds
        manifest.setdefault("round_share", 0.0)
        if {k: old.get(k) for k in keys} != {k: manifest.get(k) for k in keys}:
            return (
                f"{out} holds a different data set ({'/'.join(keys)} "
                f"{'/'.join(str(old.get(k)) for k in keys)}); use another --out"
            )
    complete = [k for k in range(len(manifest["shards"])) if shard_complete(out, k)]
    return SetFolder(settings, extra, complete)


def _error(msg: str) -> int:
    print(f"sketch2cad datagen: error: {msg}", file=sys.stderr)
    return 2


def generate_dataset(settings: DatagenSettings) -> int:
    """Make (or finish) the data set; returns the exit code (2 with the reason printed
    for bad settings or an --out that holds another data set)."""
    if settings.count <= 0:
        return _error("--count must be positive")
    if settings.shard_size <= 0 or settings.shard_size % PER_CONTEXT:
        return _error(f"--shard-size must be a positive multiple of {PER_CONTEXT}")
    if settings.workers <= 0:
        return _error("--workers must be positive")
    if settings.hand not in HANDS:
        return _error(f"--hand must be one of {', '.join(HANDS)}, got {settings.hand}")
    if not 0.0 <= settings.regular_share <= 1.0:
        return _error(f"--regular-share must be between 0 and 1, got {settings.regular_share}")
    if not 0.0 <= settings.round_share <= 1.0:
        return _error(f"--round-share must be between 0 and 1, got {settings.round_share}")
    if settings.ray is not None:
        from .cluster import require_ray  # Ray is an optional extra

        try:
            require_ray()
        except RuntimeError as e:
            return _error(str(e))
    out: Path = settings.out
    folder = open_set_folder(settings)
    if isinstance(folder, str):
        return _error(folder)
    size = settings.shard_size
    complete, done = folder.complete, folder.done
    todo = sorted(set(range(len(manifest_of(settings, [])["shards"]))) - set(complete))
    counts = {k: min(size, settings.count - k * size) for k in todo}
    done(None)
    made = sum(counts.values())
    start = time.perf_counter()
    with tqdm(
        total=settings.count,
        initial=settings.count - made,
        unit="sample",
        desc="datagen",
        smoothing=0.05,
    ) as bar:
        if settings.ray is not None:
            from .cluster import run_on_ray

            try:
                failed = run_on_ray(settings, counts, bar, done)
            except ConnectionError as e:  # no cluster at that address
                return _error(f"--ray {settings.ray}: {e}")
            if failed:
                return _error(
                    f"{len(failed)} shard(s) failed, the rest are written: " + "; ".join(failed)
                )
        else:
            jobs = [
                job
                for k in todo
                for job in shard_jobs(
                    settings.seed,
                    settings.noise_level,
                    settings.hidden_lines,
                    k,
                    counts[k],
                    size,
                    settings.regular_share,
                    settings.hand,
                    settings.shells,
                    settings.round_share,
                )
            ]
            if settings.workers == 1:
                _collect(map(make_block, jobs), todo, counts, out, bar, done)
            else:
                try:
                    _collect(
                        made_in_pool(make_block, jobs, settings.workers),
                        todo,
                        counts,
                        out,
                        bar,
                        done,
                    )
                except WorkerDied as e:
                    return _error(
                        f"{e}; the {len(complete)} shard(s) written are kept, and "
                        f"the same command makes the rest"
                    )
    secs = time.perf_counter() - start
    if made:
        where = "on Ray" if settings.ray is not None else f"with {settings.workers} worker(s)"
        print(
            f"datagen: {made} samples in {secs:.0f} s = {made / secs:.2f} samples/s {where}; "
            f"{settings.count} in {out}"
        )
    if settings.preview:
        write_preview(Dataset(out), settings.preview)
        print(f"datagen: preview written to {settings.preview}")
    return 0


def _collect(
    blocks, todo: list[int], counts: dict[int, int], out: Path, bar: tqdm, done=lambda k: None
) -> None:
    """Gather blocks (in job order) into the shards `todo`, write each when full and
    call done(k)."""
    if not todo:  # a finished set run again: nothing to make
        return
    shards = iter(todo)
    k, records = next(shards), []
    for block in blocks:
        kept = block[: counts[k] - len(records)]  # the last shard may end inside a block
        records += kept
        bar.update(len(kept))
        if len(records) == counts[k]:
            write_shard(out, k, records)
            done(k)
            k, records = next(shards, None), []
