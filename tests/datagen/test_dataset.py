# SPDX-License-Identifier: LGPL-2.1-or-later
"""The data set reader returns what was written, sample by sample and shard by shard."""

import json

import numpy as np
import pytest

from datagen.dataset import ARRAYS, FORMAT, VERSION, Dataset, write_shard


def _manifest(folder, count, shard_size, shards, version=VERSION):
    (folder / "manifest.json").write_text(
        json.dumps(
            {
                "format": FORMAT,
                "version": version,
                "count": count,
                "shard_size": shard_size,
                "shards": [f"shard-{k:05d}.npz" for k in range(shards)],
            }
        )
    )


@pytest.fixture(scope="module")
def written(tmp_path_factory, per_operator):
    samples = [s for group in per_operator.values() for s in group]
    folder = tmp_path_factory.mktemp("set")
    write_shard(folder, 0, samples[:5])
    write_shard(folder, 1, samples[5:])
    _manifest(folder, len(samples), 5, 2)
    return folder, samples


def test_the_reader_returns_what_was_written(written):
    folder, samples = written
    ds = Dataset(folder)
    assert len(ds) == len(samples) and ds.shards == [0, 1]
    for i, s in enumerate(samples):
        back = ds.sample(i)
        assert back.op_type is s.op_type and back.noise_level == s.noise_level
        assert back.operation == s.operation and back.context == s.context
        assert back.camera == s.camera and back.stroke_parts == s.stroke_parts
        for name in ("sketch", "stroke_mask", "face_label", "curve_label", "face_id"):
            assert np.array_equal(getattr(back, name), getattr(s, name)), name
        assert np.allclose(back.depth, s.depth, atol=1e-3)  # float16
        assert np.allclose(back.normal, s.normal, atol=1e-3)
        assert all(
            np.allclose(a, b, atol=1e-3) for a, b in zip(back.strokes, s.strokes, strict=True)
        )


def test_fast_access_gives_the_network_inputs_and_labels(written):
    folder, samples = written
    ds = Dataset(folder)
    i = 6
    assert np.allclose(ds.inputs(i), samples[i].inputs(), atol=1e-3)
    a = ds.arrays(i)
    assert a["inputs"].shape == (5, 256, 256) and a["inputs"].dtype == np.float32
    assert np.array_equal(a["curve_label"], samples[i].curve_label)
    assert a["op_type"] == list(type(samples[i].op_type)).index(samples[i].op_type)
    batches = list(ds.batches())
    assert [k for k, _ in batches] == [0, 1]
    assert [len(b) for _, b in batches] == [5, len(samples) - 5]
    assert np.allclose(batches[1][1].inputs[1], ds.inputs(6))


def test_shards_are_stored_compactly(written):
    folder, _ = written
    with np.load(folder / "shard-00000.npz") as z:
        assert {name: str(z[name].dtype) for name in z.files} == ARRAYS


def test_an_incomplete_shard_is_not_read(written, tmp_path):
    folder, samples = written
    for name in ("shard-00000.npz", "shard-00001.npz", "shard-00000.json"):
        (tmp_path / name).write_bytes((folder / name).read_bytes())
    _manifest(tmp_path, len(samples), 5, 2)
    ds = Dataset(tmp_path)
    assert ds.shards == [0] and len(ds) == 5
    with pytest.raises(IndexError):
        ds.sample(5)


def test_version_1_sets_with_8_bit_maps_still_read(written, tmp_path):
    folder, samples = written
    with np.load(folder / "shard-00000.npz") as z:
        arrays = {name: z[name] for name in z.files}
    arrays["depth"] = np.round(arrays["depth"].astype(np.float32) * 255).astype(np.uint8)
    arrays["normal"] = np.round(arrays["normal"].astype(np.float32) * 127.5).astype(np.uint8)
    np.savez_compressed(tmp_path / "shard-00000.npz", **arrays)
    (tmp_path / "shard-00000.json").write_bytes((folder / "shard-00000.json").read_bytes())
    _manifest(tmp_path, 5, 5, 1, version=1)
    back = Dataset(tmp_path).sample(2)
    assert np.allclose(back.depth, samples[2].depth, atol=1 / 255)
    assert np.allclose(back.normal, samples[2].normal, atol=1 / 127)
