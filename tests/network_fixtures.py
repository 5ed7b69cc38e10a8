# SPDX-License-Identifier: LGPL-2.1-or-later
"""Fixtures for the network tests: a tiny model config and tiny on-disk data sets."""

import json

import numpy as np
import pytest

from datagen.dataset import FORMAT, VERSION, Record, write_shard
from Sketch2CADWorkbench.inference.models import ModelConfig

SIZE = 32  # side of the tiny maps


@pytest.fixture
def tiny_config() -> ModelConfig:
    return ModelConfig(
        image_size=SIZE, internal_size=SIZE // 2, widths=(8, 16, 32), classifier_hidden=8
    )


def synthetic_record(rng: np.random.Generator, op: int, noise: int, size: int = SIZE) -> Record:
    """A learnable toy sample: a box seen as two faces (left, right), strokes forming a
    rectangle on one of them (the base face), the operator coded in the strokes' layout."""
    split = size // 2 + int(rng.integers(-3, 4))
    top, bottom = 4, size - 4
    normal = np.zeros((3, size, size), np.float32)
    normal[:, top:bottom, 4:split] = np.array([0.5, 1.0, 1.8])[:, None, None]
    normal[:, top:bottom, split : size - 4] = np.array([1.6, 1.0, 1.7])[:, None, None]
    depth = np.zeros((size, size), np.float32)
    depth[top:bottom, 4 : size - 4] = np.linspace(0.2, 1.0, size - 8)[None]
    left = rng.random() < 0.5
    face = np.zeros((size, size), np.uint8)
    x0, x1 = (4, split) if left else (split, size - 4)
    face[top:bottom, x0:x1] = 1
    sketch = np.zeros((size, size), np.uint8)
    curve = np.zeros((size, size), np.uint8)
    r0, r1 = top + 3 + op, bottom - 3
    c0, c1 = x0 + 2, x1 - 2
    sketch[r0, c0:c1] = sketch[r1, c0:c1] = 1  # horizontal strokes: class 1
    sketch[r0:r1, c0] = sketch[r0:r1, c1 - 1] = 1  # vertical strokes: class 0 (or 2)
    curve[r0, c0:c1] = curve[r1, c0:c1] = 1
    if op in (2, 3):  # a prism's or sweep's end on the side f's normal points to, as drawn
        curve[r0:r1, c0 if left else c1 - 1] = 2
    face_id = np.where(normal[0] == 0, -1, np.where(normal[0] < 1, 0, 1)).astype(np.int16)
    arrays = {
        "sketch": sketch,
        "stroke_mask": sketch.copy(),
        "face_label": face,
        "curve_label": curve * sketch,
        "depth": depth.astype(np.float16),
        "normal": normal.astype(np.float16),
        "face_id": face_id,
        "op_type": np.uint8(op),
        "noise_level": np.uint8(noise),
    }
    return Record(arrays, {})


def _write_dataset(folder, count: int, shard_size: int, seed: int = 0, size: int = SIZE):
    """A data set folder in the datagen format (ops 1:1:4:2 as the paper's, noise 1..3)."""
    folder.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    ops = [0, 1, 2, 2, 2, 2, 3, 3]
    records = [synthetic_record(rng, ops[i % 8], 1 + (i // 4) % 3, size) for i in range(count)]
    shards = [records[k : k + shard_size] for k in range(0, count, shard_size)]
    for k, recs in enumerate(shards):
        write_shard(folder, k, recs)
    (folder / "manifest.json").write_text(
        json.dumps(
            {
                "format": FORMAT,
                "version": VERSION,
                "count": count,
                "seed": seed,
                "noise": "mix",
                "image_size": size,
                "shard_size": shard_size,
                "per_context": 4,
                "shards": [f"shard-{k:05d}.npz" for k in range(len(shards))],
            }
        )
    )
    return folder


@pytest.fixture(scope="session")
def tiny_data(tmp_path_factory):
    """48 toy samples in 3 shards."""
    return _write_dataset(tmp_path_factory.mktemp("tiny-data"), 48, 16)


@pytest.fixture
def write_dataset():
    """write_dataset(folder, count, shard_size, seed=0, size=32) -> folder."""
    return _write_dataset
