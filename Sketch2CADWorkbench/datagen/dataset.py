# SPDX-License-Identifier: LGPL-2.1-or-later
"""On-disk data sets: compressed shards of samples plus a manifest.

Layout of a data set folder::

    manifest.json          {"format": "sketch2cad-dataset", "version": 1, "count": N,
                            "seed": S, "noise_levels": [..], "image_size": 256,
                            "shard_size": K, "shards": ["shard-00000.npz", ...]}
    shard-00000.npz        arrays, first axis = sample (uint8 maps, see ARRAYS)
    shard-00000.json       per sample: context protocol, operation, camera, strokes, labels

Maps are stored as uint8: S, F~, M~ as 0/1, C~ as its label, D as round(255 D),
N as round(127.5 N) (so N is exact to 1/127.5), face IDs as int16.
"""
from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..brep.protocol import (OperatorType, operation_from_dict, operation_to_dict,
                             protocol_from_dict, protocol_to_dict)
from ..render.camera import OrthoCamera
from .sample import Sample

FORMAT = "sketch2cad-dataset"
VERSION = 1
CLASSES = list(OperatorType)


def shard_name(k: int) -> str:
    return f"shard-{k:05d}"


def _atomic_write(path: Path, write) -> None:
    tmp = path.with_name(path.name + ".tmp")
    with open(tmp, "wb") as f:
        write(f)
    os.replace(tmp, path)


def write_shard(folder: Path, k: int, samples: list[Sample]) -> None:
    """Write one shard (arrays first, metadata last: the .json marks it complete)."""
    arrays = {
        "sketch": np.stack([s.sketch > 0 for s in samples]).astype(np.uint8),
        "depth": np.stack([np.round(s.depth * 255) for s in samples]).astype(np.uint8),
        "normal": np.stack([np.round(s.normal * 127.5) for s in samples]).astype(np.uint8),
        "face_id": np.stack([s.face_id for s in samples]).astype(np.int16),
        "face_label": np.stack([s.face_label > 0 for s in samples]).astype(np.uint8),
        "curve_label": np.stack([s.curve_label for s in samples]).astype(np.uint8),
        "stroke_mask": np.stack([s.stroke_mask > 0 for s in samples]).astype(np.uint8),
        "op_type": np.array([CLASSES.index(s.op_type) for s in samples], np.uint8),
        "noise_level": np.array([s.noise_level for s in samples], np.uint8),
    }
    _atomic_write(folder / f"{shard_name(k)}.npz", lambda f: np.savez_compressed(f, **arrays))
    meta = [{"context": protocol_to_dict(s.context), "operation": operation_to_dict(s.operation),
             "camera": s.camera.to_dict(),
             "strokes": [np.round(st, 3).tolist() for st in s.strokes],
             "stroke_parts": list(map(int, s.stroke_parts))} for s in samples]
    _atomic_write(folder / f"{shard_name(k)}.json", lambda f: f.write(json.dumps(meta).encode()))


def shard_complete(folder: Path, k: int) -> bool:
    return (folder / f"{shard_name(k)}.json").exists() and (folder / f"{shard_name(k)}.npz").exists()


@dataclass
class Batch:
    """Network-ready arrays of many samples (first axis = sample).

    inputs (N, 5, H, W) float32 (S, D, N); face_label, curve_label, stroke_mask
    (N, H, W) float32; op_type (N,) int64; noise_level (N,) int64.
    """

    inputs: np.ndarray
    face_label: np.ndarray
    curve_label: np.ndarray
    stroke_mask: np.ndarray
    op_type: np.ndarray
    noise_level: np.ndarray


def decode_inputs(a: dict[str, np.ndarray], sl=slice(None)) -> np.ndarray:
    """Stored uint8 maps -> (N, 5, H, W) float32 network inputs S, D, N."""
    return np.concatenate([a["sketch"][sl][:, None].astype(np.float32),
                           a["depth"][sl][:, None].astype(np.float32) / 255.0,
                           a["normal"][sl].astype(np.float32) / 127.5], axis=1)


class Dataset:
    """A generated data set; complete shards only are read."""

    def __init__(self, folder: str | Path):
        self.folder = Path(folder)
        path = self.folder / "manifest.json"
        if not path.exists():
            raise FileNotFoundError(f"{self.folder}: no manifest.json (not a data set folder)")
        self.manifest = json.loads(path.read_text())
        if self.manifest.get("format") != FORMAT:
            raise ValueError(f"{path}: not a {FORMAT} manifest")
        self.shard_size = int(self.manifest["shard_size"])
        self.shards = [k for k in range(len(self.manifest["shards"]))
                       if shard_complete(self.folder, k)]
        self._cache: dict[int, dict[str, np.ndarray]] = {}

    def shard_count(self, k: int) -> int:
        """How many samples shard k holds."""
        return min(self.shard_size, int(self.manifest["count"]) - k * self.shard_size)

    def __len__(self) -> int:
        return sum(self.shard_count(k) for k in self.shards)

    def arrays(self, k: int) -> dict[str, np.ndarray]:
        """All stored arrays of shard k (cached)."""
        if k not in self._cache:
            with np.load(self.folder / f"{shard_name(k)}.npz") as z:
                self._cache[k] = {name: z[name] for name in z.files}
        return self._cache[k]

    def batch(self, k: int) -> Batch:
        """Shard k as network-ready arrays."""
        a = self.arrays(k)
        return Batch(decode_inputs(a), a["face_label"].astype(np.float32),
                     a["curve_label"].astype(np.float32), a["stroke_mask"].astype(np.float32),
                     a["op_type"].astype(np.int64), a["noise_level"].astype(np.int64))

    def samples(self, k: int) -> list[Sample]:
        """Shard k as full Samples, with the ground truth for end-to-end evaluation."""
        a = self.arrays(k)
        meta = json.loads((self.folder / f"{shard_name(k)}.json").read_text())
        inputs = decode_inputs(a)
        out = []
        for i, m in enumerate(meta):
            out.append(Sample(
                op_type=CLASSES[int(a["op_type"][i])], sketch=inputs[i, 0], depth=inputs[i, 1],
                normal=inputs[i, 2:5], face_id=a["face_id"][i].astype(np.int32),
                face_label=a["face_label"][i].astype(np.float32),
                curve_label=a["curve_label"][i].astype(np.float32),
                stroke_mask=a["stroke_mask"][i].astype(np.float32),
                context=protocol_from_dict(m["context"]),
                operation=operation_from_dict(m["operation"]),
                camera=OrthoCamera.from_dict(m["camera"]),
                strokes=[np.array(s) for s in m["strokes"]], stroke_parts=m["stroke_parts"],
                noise_level=int(a["noise_level"][i])))
        return out

    def all_samples(self):
        for k in self.shards:
            yield from self.samples(k)

