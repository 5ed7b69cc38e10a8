# SPDX-License-Identifier: LGPL-2.1-or-later
"""Evaluation of the networks on a held-out data set: the paper's metrics (metrics.py) over
every sample, example predictions for the report, and the networks' latency:
the median wall time of `predict` (pooling, network, upsampling of every output to
256 x 256) on one sketch (batch 1) at 2 threads, over the first samples.
"""
from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

import numpy as np
import torch
from tqdm import tqdm

from datagen.dataset import Dataset, decode_inputs

from .metrics import Tally, curve_hits, face_overlap

LATENCY_THREADS = 2
EXAMPLES_PER_OP = 2


def latency_ms(model, inputs: list[np.ndarray], threads: int = LATENCY_THREADS) -> float:
    """Median ms of model.predict on one (5, S, S) sketch at a time, `threads` threads."""
    before = torch.get_num_threads()
    torch.set_num_threads(threads)
    model.predict(torch.from_numpy(inputs[0])[None])  # first call allocates
    times = []
    for x in inputs:
        t = time.perf_counter()
        model.predict(torch.from_numpy(x)[None])
        times.append(1e3 * (time.perf_counter() - t))
    torch.set_num_threads(before)
    return statistics.median(times)


def evaluate(data: Path, weights: Path | None = None, limit: int | None = None,
             latency_runs: int = 50, batch: int = 32) -> tuple[dict, list[dict]]:
    """The metrics of the JSON and a few example predictions for the report.

    Args:
        data: data set folder; weights: file or folder (None: the shipped weights);
        limit: use the first `limit` samples only; latency_runs: sketches timed one by
        one; batch: samples per forward pass for the metrics (the outputs do not depend
        on it: batch norm uses its running statistics at inference).
    Returns:
        the result dictionary and example predictions (numpy maps per sample).
    """
    from Sketch2CADWorkbench.inference.weights import load_model, resolve
    path = resolve(weights)
    model, ckpt = load_model(path)
    ds = Dataset(data)
    n_total = min(len(ds), limit) if limit else len(ds)
    if n_total == 0:
        raise ValueError(f"{data}: the data set has no complete shard yet")
    tally, examples, timed = Tally(), [], []
    done = 0
    with tqdm(total=n_total, desc="eval", unit="sample", leave=False) as bar:
        for k in ds.shards:
            a = ds.shard_arrays(k)
            m = min(len(a["op_type"]), n_total - done)
            for i in range(0, m, batch):
                sl = slice(i, min(i + batch, m))
                x = decode_inputs(a, sl)                                       # (B, 5, S, S)
                probs, f, c = model.predict(torch.from_numpy(x))
                op = torch.from_numpy(a["op_type"][sl].astype(np.int64))
                face = torch.from_numpy(a["face_label"][sl].astype(np.float32))
                curve = torch.from_numpy(a["curve_label"][sl].astype(np.float32))
                mask = torch.from_numpy(a["stroke_mask"][sl].astype(np.float32))
                rows = torch.arange(len(op))
                fo, co = f[rows, op], c[rows, op]       # the true operator's maps (B, S, S)
                tally.add(op, probs.argmax(1), torch.from_numpy(a["noise_level"][sl]),
                          *face_overlap(fo, face), *curve_hits(co, curve, mask, op))
                for j in range(len(op)):
                    if len(timed) < latency_runs:
                        timed.append(x[j])
                    if sum(e["op"] == int(op[j]) for e in examples) < EXAMPLES_PER_OP:
                        examples.append({"op": int(op[j]), "pred": int(probs[j].argmax()),
                                         "sketch": x[j, 0], "depth": x[j, 1],
                                         "face": fo[j].numpy(), "face_label": face[j].numpy(),
                                         "curve": co[j].numpy(), "curve_label": curve[j].numpy(),
                                         "mask": mask[j].numpy()})
                bar.update(len(op))
            done += m
            if done >= n_total:
                break
    result = tally.summary()
    result["latency_ms"] = {"networks_median": latency_ms(model, timed),
                            "runs": len(timed), "threads": LATENCY_THREADS}
    result["data"] = {"path": str(data), "seed": ds.manifest.get("seed"),
                      "noise": ds.manifest.get("noise")}
    result["weights"] = {"path": str(path), "config": ckpt["config"],
                         "trained_on": ckpt.get("data_key")}
    trained = ckpt.get("data_key") or {}
    if trained.get("seed") == ds.manifest.get("seed") and trained.get("count") == len(ds):
        print(f"sketch2cad eval: warning: {data} looks like the training data set (same seed "
              "and size); generate a held-out set with another --seed", file=sys.stderr)
    order = sorted(range(len(examples)), key=lambda e: examples[e]["op"])
    return result, [examples[e] for e in order]


def has_ground_truth(data: Path) -> bool:
    """Whether the data set's shards keep each sample's context and operation."""
    ds = Dataset(data)
    return bool(ds.shards) and "context" in ds.shard_meta(ds.shards[0])[0]
