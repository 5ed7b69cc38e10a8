# SPDX-License-Identifier: LGPL-2.1-or-later
"""The training data in memory: a generated data set pooled once to the network's internal
size and held as bytes (inputs at I x I, labels at full size), cached in the run folder
so that a resumed or repeated run skips that step; and the training/validation split."""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import torch
import torch.nn.functional as F
from tqdm import tqdm

from datagen.dataset import Dataset, decode_inputs
from Sketch2CADWorkbench.brep.files import atomic_path
from Sketch2CADWorkbench.inference.models import ModelConfig, Sketch2CADNet


@dataclass
class PooledData:
    """Samples ready for the network, compactly (first axis = sample).

    x: (N, 6, I, I) uint8: S, round(255 D), round(127.5 N) x 3, and round(255 a), a the
       foreground share of each pooled pixel (exact mirror images of N need it).
    labels: (N, S, S) uint8 at full size: bit 0 is F~; bits 1-2 hold 1 + C~ on stroke
       pixels (M~ = 1) and 0 off them.
    op: (N,) int64 operator index; noise: (N,) int64 noise level.
    """

    x: torch.Tensor
    labels: torch.Tensor
    op: torch.Tensor
    noise: torch.Tensor

    def __len__(self) -> int:
        return len(self.op)

    def subset(self, idx) -> PooledData:
        return PooledData(self.x[idx], self.labels[idx], self.op[idx], self.noise[idx])

    def batch(
        self, idx: torch.Tensor, device: str, flip: torch.Tensor | None = None
    ) -> tuple[torch.Tensor, ...]:
        """Decode samples `idx`: inputs (B, 5, I, I), F~, C~, M~ (B, S, S), op (B,).

        flip: (B,) bool, which samples to mirror left-right. A mirrored scene is a valid
        scene: the maps flip and the camera-space normal's x changes sign, which on the
        pooled N = a (n + 1) reads 2a - N_x.
        """
        x = self.x[idx].to(device).float()
        lab = self.labels[idx].to(device)
        if flip is not None and flip.any():
            f = flip.to(device)
            x[f] = x[f].flip(-1)
            x[f, 2] = (x[f, 5] - x[f, 2]).clamp(min=0)  # 127.5 (2a - N_x) in storage units
            lab[f] = lab[f].flip(-1)
        x = torch.cat([x[:, :1], x[:, 1:2] / 255.0, x[:, 2:5] / 127.5], 1)
        code = (lab >> 1).float()
        mask = (code > 0).float()
        curve = (code - 1).clamp(min=0)
        return x, (lab & 1).float(), curve, mask, self.op[idx].to(device)


def pool_dataset(ds: Dataset, model: Sketch2CADNet, chunk: int = 32) -> PooledData:
    """All complete shards of `ds`, pooled with the model's own `pool` (the inputs then
    match what `predict` feeds the network, up to the 8-bit storage)."""
    n, i, s = len(ds), model.config.internal_size, model.config.image_size
    data = PooledData(
        torch.empty(n, 6, i, i, dtype=torch.uint8),
        torch.empty(n, s, s, dtype=torch.uint8),
        torch.empty(n, dtype=torch.int64),
        torch.empty(n, dtype=torch.int64),
    )
    start = 0
    for k in tqdm(ds.shards, desc="pooling data set", unit="shard", leave=False):
        a = ds.shard_arrays(k)
        for j in range(0, len(a["op_type"]), chunk):
            sl = slice(j, j + chunk)
            full = torch.from_numpy(decode_inputs(a, sl))  # (b, 5, S, S)
            b = len(full)
            fg = (full[:, 2:5].sum(1, keepdim=True) > 0).float()  # (b, 1, S, S)
            with torch.no_grad():
                pooled = model.pool(full)  # (b, 5, I, I)
                share = F.adaptive_avg_pool2d(fg, pooled.shape[-2:])
            q = torch.cat(
                [pooled[:, :1], pooled[:, 1:2] * 255, pooled[:, 2:5] * 127.5, share * 255], 1
            )
            data.x[start : start + b] = q.round().clamp(0, 255).to(torch.uint8)
            stroke = a["stroke_mask"][sl] > 0
            code = np.where(stroke, a["curve_label"][sl].astype(np.uint8) + 1, 0) << 1
            data.labels[start : start + b] = torch.from_numpy(
                (code | (a["face_label"][sl] > 0)).astype(np.uint8)
            )
            data.op[start : start + b] = torch.from_numpy(a["op_type"][sl].astype(np.int64))
            data.noise[start : start + b] = torch.from_numpy(a["noise_level"][sl].astype(np.int64))
            start += b
    return data


def data_key(ds: Dataset, config: ModelConfig) -> dict:
    """What identifies a pooled data set: the data set and the pooling."""
    m = ds.manifest
    return {
        "data": str(ds.folder.resolve()),
        "count": len(ds),
        "seed": m.get("seed"),
        "noise": m.get("noise"),
        "version": m.get("version"),
        "image_size": config.image_size,
        "internal_size": config.internal_size,
    }


def load_pooled(ds: Dataset, model: Sketch2CADNet, out: Path) -> PooledData:
    """The pooled data set, from the run folder's cache when it matches `ds`."""
    key = data_key(ds, model.config)
    path = out / f"data-cache-{model.config.internal_size}.pt"
    if path.exists():
        cached = torch.load(path, mmap=True, weights_only=True)
        if cached["key"] == json.dumps(key, sort_keys=True):
            return PooledData(cached["x"], cached["labels"], cached["op"], cached["noise"])
    data = pool_dataset(ds, model)
    with atomic_path(path) as tmp:
        torch.save({"key": json.dumps(key, sort_keys=True), **asdict(data)}, tmp)
    return data


def split(n: int, fraction: float, block: int) -> tuple[slice, slice]:
    """Training and validation samples: the validation set is the last fraction n
    samples rounded up to whole blocks of `block` (samples sharing a context stay on
    one side). Slices, so that the subsets are views, not copies."""
    n_val = 0 if n < 2 * block else min(n - block, block * math.ceil(fraction * n / block))
    return slice(0, n - n_val), slice(n - n_val, n)
