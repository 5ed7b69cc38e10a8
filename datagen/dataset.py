# SPDX-License-Identifier: LGPL-2.1-or-later
"""On-disk data sets: compressed shards of samples, per-shard metadata, and a manifest.

Layout of a data set folder (format "sketch2cad-dataset", version 2)::

    manifest.json     {"format": "sketch2cad-dataset", "version": 2, "count": N,
                       "seed": S, "noise": "1"|"2"|"3"|"mix", "noise_levels": [..],
                       "hidden_lines": "draw"|"omit"|"mix", "regular_share": P,
                       "round_share": P (only when above 0),
                       "image_size": 256, "shard_size": K, "per_context": 4,
                       "arrays": {name: dtype}, "shards": ["shard-00000.npz", ...]}
    shard-00000.npz   one array per name, first axis = sample (ARRAYS below)
    shard-00000.json  one object per sample: "context" (protocol JSON), "operation",
                      "camera" (OrthoCamera.to_dict), "strokes" (pixel polylines,
                      rounded to 1/1000 px), "stroke_parts" (curve label per stroke)

Arrays (H x W maps in the camera's pixel convention, render/camera.py):
    sketch, stroke_mask, face_label: uint8 0/1; curve_label: uint8 label;
    depth: float16 (N, H, W); normal: float16 (N, 3, H, W); face_id: int16 (-1 none);
    op_type: uint8 index into sketch.labels.LABELLED; noise_level: uint8.
Version 1 sets (depth as round(255 D), normal as round(127.5 N), both uint8) are still
read; their maps decode to within 1/255 and 1/127.5.

A shard is written to a temporary name and renamed, the .npz first and the .json last,
so an existing .json marks a complete shard and an interrupted run leaves none half
written.
"""

from __future__ import annotations

import json
import zipfile
from collections import OrderedDict
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from Sketch2CADWorkbench.brep.files import atomic_path
from Sketch2CADWorkbench.brep.protocol import (
    operation_from_dict,
    protocol_from_dict,
    protocol_to_dict,
)
from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.sketch.labels import LABELLED

from .sample import Sample

FORMAT = "sketch2cad-dataset"
VERSION = 2
ARRAYS = {
    "sketch": "uint8",
    "stroke_mask": "uint8",
    "face_label": "uint8",
    "curve_label": "uint8",
    "depth": "float16",
    "normal": "float16",
    "face_id": "int16",
    "op_type": "uint8",
    "noise_level": "uint8",
}
COMPRESS_LEVEL = 3  # zlib level of the shards: speed over size (docs/measurements.md)
CACHED_SHARDS = 2  # decoded shards kept by a reader (a shard is ~100 MB decoded)


def shard_name(k: int) -> str:
    return f"shard-{k:05d}"


@dataclass
class Record:
    """One sample in storage form: its arrays (ARRAYS dtypes, no sample axis) and its
    JSON metadata."""

    arrays: dict[str, np.ndarray]
    meta: dict


def pack(s: Sample) -> Record:
    """A sample in storage form (about 0.8 MB instead of 2.4 MB in memory)."""
    arrays = {
        "sketch": s.sketch > 0,
        "stroke_mask": s.stroke_mask > 0,
        "face_label": s.face_label > 0,
        "curve_label": s.curve_label,
        "depth": s.depth,
        "normal": s.normal,
        "face_id": s.face_id,
        "op_type": LABELLED.index(s.op_type),
        "noise_level": s.noise_level,
    }
    meta = {
        "context": protocol_to_dict(s.context),
        "operation": s.operation.to_dict(),
        "camera": s.camera.to_dict(),
        "strokes": [np.round(st, 3).tolist() for st in s.strokes],
        "stroke_parts": [int(p) for p in s.stroke_parts],
    }
    return Record({k: np.asarray(v).astype(ARRAYS[k]) for k, v in arrays.items()}, meta)


def _replace_atomically(path: Path, write) -> None:
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        write(f)


def _write_npz(f, arrays: dict[str, np.ndarray]) -> None:
    """An .npz (np.load reads it) with a faster compression level than numpy's."""
    with zipfile.ZipFile(f, "w", zipfile.ZIP_DEFLATED, compresslevel=COMPRESS_LEVEL) as z:
        for name, a in arrays.items():
            with z.open(name + ".npy", "w", force_zip64=True) as member:
                np.lib.format.write_array(member, np.ascontiguousarray(a))


def write_shard(folder: Path, k: int, records: list[Record | Sample]) -> None:
    """Write shard k (samples are packed first); complete once its .json exists."""
    records = [r if isinstance(r, Record) else pack(r) for r in records]
    arrays = {name: np.stack([r.arrays[name] for r in records]) for name in ARRAYS}
    folder = Path(folder)
    _replace_atomically(folder / f"{shard_name(k)}.npz", lambda f: _write_npz(f, arrays))
    meta = json.dumps([r.meta for r in records]).encode()
    _replace_atomically(folder / f"{shard_name(k)}.json", lambda f: f.write(meta))


def shard_complete(folder: Path, k: int) -> bool:
    folder = Path(folder)
    return (folder / f"{shard_name(k)}.json").exists() and (
        folder / f"{shard_name(k)}.npz"
    ).exists()


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

    def __len__(self) -> int:
        return len(self.op_type)


def _depth(a: np.ndarray) -> np.ndarray:
    return a.astype(np.float32) / 255.0 if a.dtype == np.uint8 else a.astype(np.float32)


def _normal(a: np.ndarray) -> np.ndarray:
    return a.astype(np.float32) / 127.5 if a.dtype == np.uint8 else a.astype(np.float32)


def decode_inputs(a: dict[str, np.ndarray], sl=slice(None)) -> np.ndarray:
    """Stored maps -> (N, 5, H, W) float32 network inputs S, D, N."""
    return np.concatenate(
        [
            a["sketch"][sl][:, None].astype(np.float32),
            _depth(a["depth"][sl])[:, None],
            _normal(a["normal"][sl]),
        ],
        axis=1,
    )


def decode_batch(a: dict[str, np.ndarray], sl=slice(None)) -> Batch:
    """Stored arrays (of a shard, or a slice of one) -> a Batch."""
    return Batch(
        decode_inputs(a, sl),
        a["face_label"][sl].astype(np.float32),
        a["curve_label"][sl].astype(np.float32),
        a["stroke_mask"][sl].astype(np.float32),
        a["op_type"][sl].astype(np.int64),
        a["noise_level"][sl].astype(np.int64),
    )


class Dataset:
    """A generated data set, read-only; only complete shards count.

    Samples are numbered 0 .. len - 1 over the complete shards in order. For training,
    stream it shard by shard with `batches()` (or `batch(k)`); for looking at single
    samples use `inputs(i)`, `arrays(i)` and `sample(i)`.
    """

    def __init__(self, folder: str | Path):
        self.folder = Path(folder)
        path = self.folder / "manifest.json"
        if not path.exists():
            raise FileNotFoundError(f"{self.folder}: no manifest.json (not a data set folder)")
        self.manifest = json.loads(path.read_text())
        if self.manifest.get("format") != FORMAT:
            raise ValueError(f"{path}: not a {FORMAT} manifest")
        if self.manifest.get("version", 1) > VERSION:
            raise ValueError(
                f"{path}: data set version {self.manifest['version']} is newer "
                f"than this reader ({VERSION})"
            )
        self.shard_size = int(self.manifest["shard_size"])
        self.shards = [
            k for k in range(len(self.manifest["shards"])) if shard_complete(self.folder, k)
        ]
        self._starts = np.cumsum([0] + [self.shard_count(k) for k in self.shards])
        self._arrays: OrderedDict[int, dict[str, np.ndarray]] = OrderedDict()
        self._meta: OrderedDict[int, list[dict]] = OrderedDict()

    def shard_count(self, k: int) -> int:
        """How many samples shard k holds."""
        return min(self.shard_size, int(self.manifest["count"]) - k * self.shard_size)

    def __len__(self) -> int:
        return int(self._starts[-1])

    # ------------------------------------------------------------ shards
    def shard_arrays(self, k: int) -> dict[str, np.ndarray]:
        """The arrays of shard k, as stored (the last CACHED_SHARDS read are kept)."""

        def load():
            with np.load(self.folder / f"{shard_name(k)}.npz") as z:
                return {name: z[name] for name in z.files}

        return _cached(self._arrays, k, load)

    def shard_meta(self, k: int) -> list[dict]:
        """The per-sample JSON metadata of shard k (the last CACHED_SHARDS are kept)."""
        return _cached(
            self._meta, k, lambda: json.loads((self.folder / f"{shard_name(k)}.json").read_text())
        )

    def batch(self, k: int) -> Batch:
        """Shard k as network-ready arrays."""
        return decode_batch(self.shard_arrays(k))

    def batches(self) -> Iterator[tuple[int, Batch]]:
        """(k, batch) for every complete shard in order: one shard in memory at a time."""
        for k in self.shards:
            yield k, self.batch(k)

    def samples(self, k: int) -> list[Sample]:
        """Shard k as full Samples, with the ground truth for end-to-end evaluation."""
        a, meta = self.shard_arrays(k), self.shard_meta(k)
        return [_sample(a, i, m) for i, m in enumerate(meta)]

    def all_samples(self) -> Iterator[Sample]:
        for k in self.shards:
            yield from self.samples(k)

    # ------------------------------------------------------------ single samples
    def locate(self, i: int) -> tuple[int, int]:
        """(shard, position in it) of sample i."""
        if not 0 <= i < len(self):
            raise IndexError(f"sample {i} out of range 0..{len(self) - 1}")
        j = int(np.searchsorted(self._starts, i, side="right")) - 1
        return self.shards[j], i - int(self._starts[j])

    def inputs(self, i: int) -> np.ndarray:
        """The (5, H, W) float32 network input of sample i (S, D, N)."""
        k, j = self.locate(i)
        return decode_inputs(self.shard_arrays(k), slice(j, j + 1))[0]

    def arrays(self, i: int) -> dict[str, np.ndarray]:
        """Network input and labels of sample i: inputs (5, H, W), face_label,
        curve_label, stroke_mask (H, W) float32, op_type and noise_level (ints)."""
        k, j = self.locate(i)
        b = decode_batch(self.shard_arrays(k), slice(j, j + 1))
        return {
            "inputs": b.inputs[0],
            "face_label": b.face_label[0],
            "curve_label": b.curve_label[0],
            "stroke_mask": b.stroke_mask[0],
            "op_type": int(b.op_type[0]),
            "noise_level": int(b.noise_level[0]),
        }

    def sample(self, i: int) -> Sample:
        """Sample i with everything, ground truth included."""
        k, j = self.locate(i)
        return _sample(self.shard_arrays(k), j, self.shard_meta(k)[j])


def _cached(cache: OrderedDict, k: int, load):
    """cache[k], loaded on a miss; the least recently used entries beyond CACHED_SHARDS
    are dropped."""
    if k in cache:
        cache.move_to_end(k)
    else:
        cache[k] = load()
        while len(cache) > CACHED_SHARDS:
            cache.popitem(last=False)
    return cache[k]


def _sample(a: dict[str, np.ndarray], i: int, m: dict) -> Sample:
    return Sample(
        op_type=LABELLED[int(a["op_type"][i])],
        sketch=a["sketch"][i].astype(np.float32),
        depth=_depth(a["depth"][i]),
        normal=_normal(a["normal"][i]),
        face_id=a["face_id"][i].astype(np.int32),
        face_label=a["face_label"][i].astype(np.float32),
        curve_label=a["curve_label"][i].astype(np.float32),
        stroke_mask=a["stroke_mask"][i].astype(np.float32),
        context=protocol_from_dict(m["context"]),
        operation=operation_from_dict(m["operation"]),
        camera=OrthoCamera.from_dict(m["camera"]),
        strokes=[np.array(s, dtype=float).reshape(-1, 2) for s in m["strokes"]],
        stroke_parts=[int(p) for p in m["stroke_parts"]],
        noise_level=int(a["noise_level"][i]),
    )
