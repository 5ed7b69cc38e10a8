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
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch
from tqdm import tqdm

from datagen.dataset import Dataset, decode_inputs
from Sketch2CADWorkbench.inference.head.checkpoint import load_head
from Sketch2CADWorkbench.inference.head.model import StructureHead, collate
from Sketch2CADWorkbench.inference.head.paint import painted
from Sketch2CADWorkbench.inference.head.tokens import Tokens, UNetPass, feature_maps, tokens
from Sketch2CADWorkbench.inference.models import Sketch2CADNet
from Sketch2CADWorkbench.inference.weights import load_model, resolve
from Sketch2CADWorkbench.sketch.labels import CLASSES

from .metrics import Tally, curve_hits, face_overlap
from .pieces import sketch_pieces

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


@dataclass
class Scores:
    """What one pass of the U-Net over a data set scored, with a head's reading of its
    features beside its maps when a head was given."""

    unet: Tally
    head: Tally | None  # the head's choices painted into F and C
    examples: list[dict]  # EXAMPLES_PER_OP U-Net predictions per operator
    inputs: list[np.ndarray]  # the first `keep_inputs` sketches' inputs (5, S, S)
    data: dict  # the data set's path, seed and noise


def batch_tokens(u: UNetPass, pieces: list[list[np.ndarray]], face_id: np.ndarray) -> list[Tokens]:
    """The head's tokens of a batch's samples from the U-Net's pass over them and each
    sample's pieces of curves (`pieces.sketch_pieces`)."""
    return [tokens(u.logits[j], u.sketch(j), p, face_id[j]) for j, p in enumerate(pieces)]


def _head_reading(
    head: StructureHead,
    u: UNetPass,
    pieces: list[list[np.ndarray]],
    face_id: np.ndarray,
    op: torch.Tensor,
) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """The head's class logits (B, N_CLASSES) and its choices under the true operator
    painted into F and C (B, S, S), as the fitting reads them."""
    toks = batch_tokens(u, pieces, face_id)
    logits, roles, faces = head(*collate(toks))
    pf, pc = [], []
    for j, t in enumerate(toks):
        f, c = painted(roles[j, : len(pieces[j])], faces[j], int(op[j]), pieces[j], t, face_id[j])
        pf.append(f)
        pc.append(c)
    return logits, torch.from_numpy(np.stack(pf)), torch.from_numpy(np.stack(pc))


def score(
    data: Path,
    model: Sketch2CADNet,
    head: StructureHead | None = None,
    limit: int | None = None,
    batch: int = 32,
    keep_inputs: int = 0,
) -> Scores:
    """The paper's metrics over `data` (its first `limit` samples) from one pass of the
    U-Net per batch: its own maps, and a `head`'s choices read from the same features;
    each segmentation scored on the ground-truth operator's maps, as the paper does.
    `batch` samples per forward pass (the outputs do not depend on it: batch norm uses
    its running statistics at inference)."""
    ds = Dataset(data)
    n_total = min(len(ds), limit) if limit else len(ds)
    if n_total == 0:
        raise ValueError(f"{data}: the data set has no complete shard yet")
    out = Scores(
        Tally(),
        Tally() if head is not None else None,
        [],
        [],
        {"path": str(data), "seed": ds.manifest.get("seed"), "noise": ds.manifest.get("noise")},
    )
    done = 0
    with tqdm(total=n_total, desc="eval", unit="sample", leave=False) as bar:
        for k in ds.shards:
            a, meta = ds.shard_arrays(k), ds.shard_meta(k)
            m = min(len(a["op_type"]), n_total - done)
            for i in range(0, m, batch):
                sl = slice(i, min(i + batch, m))
                x = decode_inputs(a, sl)  # (B, 5, S, S)
                op = torch.from_numpy(a["op_type"][sl].astype(np.int64))
                noise = torch.from_numpy(a["noise_level"][sl])
                face = torch.from_numpy(a["face_label"][sl].astype(np.float32))
                curve = torch.from_numpy(a["curve_label"][sl].astype(np.float32))
                mask = torch.from_numpy(a["stroke_mask"][sl].astype(np.float32))
                rows = torch.arange(len(op))
                with torch.inference_mode():
                    u = feature_maps(model, torch.from_numpy(x))
                    probs, f, c = model.full_size(u.logits, u.f, u.c)
                    if head is not None:
                        pieces = [
                            sketch_pieces(m["strokes"], cl, sm)[0]
                            for m, cl, sm in zip(
                                meta[sl], a["curve_label"][sl], a["stroke_mask"][sl], strict=True
                            )
                        ]
                        # a head without the shell's class is scored on the others
                        known = op < head.config.classes
                        logits, pf, pc = _head_reading(
                            head, u, pieces, a["face_id"][sl], torch.where(known, op, 0)
                        )
                        hop = op[known]
                        out.head.add(
                            hop,
                            logits.argmax(1)[known],
                            noise[known],
                            *face_overlap(pf[known], face[known]),
                            *curve_hits(pc[known], curve[known], mask[known], hop),
                        )
                # the U-Net is scored on the samples of its classes, on the true
                # operator's maps (B, S, S); a shell it has no class or maps for
                own = op < len(CLASSES)
                rows, uop = rows[own], op[own]
                fo, co = f[rows, uop], c[rows, uop]
                out.unet.add(
                    uop,
                    probs[own].argmax(1),
                    noise[own],
                    *face_overlap(fo, face[own]),
                    *curve_hits(co, curve[own], mask[own], uop),
                )
                out.inputs += list(x[: max(0, keep_inputs - len(out.inputs))])
                for r, j in enumerate(rows.tolist()):
                    if sum(e["op"] == int(op[j]) for e in out.examples) < EXAMPLES_PER_OP:
                        out.examples.append(
                            {
                                "op": int(op[j]),
                                "pred": int(probs[j].argmax()),
                                "sketch": x[j, 0],
                                "depth": x[j, 1],
                                "face": fo[r].numpy(),
                                "face_label": face[j].numpy(),
                                "curve": co[r].numpy(),
                                "curve_label": curve[j].numpy(),
                                "mask": mask[j].numpy(),
                            }
                        )
                bar.update(len(op))
            done += m
            if done >= n_total:
                break
    out.examples.sort(key=lambda e: e["op"])
    return out


def evaluate(
    data: Path,
    weights: Path | None = None,
    limit: int | None = None,
    latency_runs: int = 50,
    batch: int = 32,
    head: Path | None = None,
) -> tuple[dict, list[dict]]:
    """The metrics of the JSON and a few example predictions for the report.

    Args:
        data: data set folder; weights: file or folder (None: the shipped weights);
        limit: use the first `limit` samples only; latency_runs: sketches timed one by
        one; batch: samples per forward pass for the metrics; head: a structured head
        file, whose choices are scored under "structured" from the same pass.
    Returns:
        the result dictionary and example predictions (numpy maps per sample).
    """
    path = resolve(weights)
    model, ckpt = load_model(path)
    s = score(
        data,
        model,
        load_head(head)[0] if head is not None else None,
        limit,
        batch,
        keep_inputs=latency_runs,
    )
    result = s.unet.summary()
    result["latency_ms"] = {
        "networks_median": latency_ms(model, s.inputs),
        "runs": len(s.inputs),
        "threads": LATENCY_THREADS,
    }
    result["data"] = s.data
    result["weights"] = {
        "path": str(path),
        "config": ckpt["config"],
        "trained_on": ckpt.get("data_key"),
    }
    if s.head is not None:
        result["structured"] = s.head.summary()
    trained = ckpt.get("data_key") or {}
    if trained.get("seed") == s.data["seed"] and trained.get("count") == len(Dataset(data)):
        print(
            f"sketch2cad eval: warning: {data} looks like the training data set (same seed "
            "and size); generate a held-out set with another --seed",
            file=sys.stderr,
        )
    return result, s.examples


def has_ground_truth(data: Path) -> bool:
    """Whether the data set's shards keep each sample's context and operation."""
    ds = Dataset(data)
    return bool(ds.shards) and "context" in ds.shard_meta(ds.shards[0])[0]
