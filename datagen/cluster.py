# SPDX-License-Identifier: LGPL-2.1-or-later
"""Data generation on a Ray cluster (`sketch2cad datagen --ray [ADDRESS]`).

Each missing shard is one Ray task, `parallel.make_shard` keyed by (seed, shard index):
it makes the shard's blocks and writes the shard into the output folder itself, so the
bytes are the process pool's whatever the number of workers or machines, and the folder
must be one every node sees (a shared file system). A task whose worker dies (killed,
out of memory, a node lost) is run again by Ray (RETRIES times); a task that raises is
reported by its shard and the others still finish; rerunning the command makes only
the shards still missing. Without an address Ray starts a local cluster of `--workers`
CPUs for this run; with one (`ray start --head` on one machine, `ray start
--address=HEAD:6379` on the others: README) the tasks spread over the whole cluster.

Ray is the optional extra `sketch2cad[cluster]`; only this module imports it.
"""

from __future__ import annotations

import contextlib
import logging
import os
import time
from collections.abc import Callable

from tqdm import tqdm

from .parallel import SINGLE_THREAD_ENV, DatagenSettings, make_shard

RETRIES = 3  # runs of a shard's task after its worker died
# The local cluster's shared-memory object store: the tasks return shard numbers only.
OBJECT_STORE_BYTES = 100 * 1024**2


def require_ray():
    """The ray module. Raises RuntimeError saying how to install it when missing."""
    try:
        import ray
    except ImportError:
        raise RuntimeError(
            "--ray needs Ray, the optional extra 'cluster' (`make setup`, or "
            "`SKETCH2CAD_EXTRAS=cluster freecadcmd scripts/"
            "install_dependencies.py`: README)"
        ) from None
    return ray


@contextlib.contextmanager
def ray_cluster(address: str, workers: int):
    """The ray module, connected while the block runs to the cluster at `address`, or
    ("local") to one started here with `workers` CPUs, which ends with the block."""
    ray = require_ray()
    # the workers: one thread each, and this checkout and its dependencies on the path
    # (the same folders on every node)
    env = dict(SINGLE_THREAD_ENV, PYTHONPATH=os.environ.get("PYTHONPATH", ""))
    if address == "local":
        ray.init(
            address="local",
            num_cpus=workers,
            include_dashboard=False,
            object_store_memory=OBJECT_STORE_BYTES,
            logging_level=logging.WARNING,
            runtime_env={"env_vars": env},
        )
    else:
        ray.init(address=address, logging_level=logging.WARNING, runtime_env={"env_vars": env})
    try:
        yield ray
    finally:
        ray.shutdown()


def run_on_ray(
    settings: DatagenSettings, counts: dict[int, int], bar: tqdm, done: Callable[[int], None]
) -> list[str]:
    """Make the shards `counts` (shard -> samples) as Ray tasks on the cluster
    settings.ray names; call done(k) as each is written and advance the bar. Returns one
    line per shard that failed (empty: all written)."""
    start = time.perf_counter()
    with ray_cluster(settings.ray, settings.workers) as ray:
        cpus = int(ray.cluster_resources().get("CPU", 0))
        bar.write(
            f"datagen: {len(counts)} shard task(s) on Ray, {cpus} CPU(s), up in "
            f"{time.perf_counter() - start:.0f} s"
        )
        return make_shards(ray, settings, counts, bar, done)


def make_shards(
    ray, settings: DatagenSettings, counts: dict[int, int], bar: tqdm, done: Callable[[int], None]
) -> list[str]:
    """`run_on_ray`'s work on a cluster `ray` is connected to."""
    task = ray.remote(num_cpus=1, max_retries=RETRIES)(make_shard)
    pending = {
        task.remote(
            str(settings.out.resolve()),
            settings.seed,
            settings.noise_level,
            settings.hidden_lines,
            k,
            n,
            settings.shard_size,
            settings.regular_share,
            settings.hand,
            settings.shells,
            settings.round_share,
        ): k
        for k, n in sorted(counts.items())
    }
    failed = []
    while pending:
        ready, _ = ray.wait(list(pending), num_returns=1)
        k = pending.pop(ready[0])
        try:
            ray.get(ready[0])
        except ray.exceptions.RayError as e:
            failed.append(f"shard {k}: {str(e).strip().splitlines()[-1]}")
            bar.write(f"datagen: shard {k} failed: {e}")
            continue
        done(k)
        bar.update(counts[k])
    return failed
