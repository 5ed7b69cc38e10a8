# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad datagen`: the same data with any worker count, resumable, with a preview."""
import cv2
import numpy as np
import pytest

from datagen.dataset import Dataset
from datagen.parallel import make_shard
from Sketch2CADWorkbench.cli import main

ARGS = ["--count", "14", "--seed", "3", "--shard-size", "8"]  # shards of 8 and 6 samples


def datagen(*args) -> int:
    return main(["datagen", *map(str, args)])


def _same_shards(a, b, shards=(0, 1)):
    for k in shards:
        name = f"shard-{k:05d}"
        assert (a / f"{name}.json").read_bytes() == (b / f"{name}.json").read_bytes()
        with np.load(a / f"{name}.npz") as x, np.load(b / f"{name}.npz") as y:
            assert x.files == y.files
            for f in x.files:
                assert np.array_equal(x[f], y[f]), (k, f)


@pytest.fixture(scope="module")
def one_worker(tmp_path_factory):
    out = tmp_path_factory.mktemp("one")
    assert datagen("--out", out, *ARGS, "--workers", 1) == 0
    return out


def test_two_workers_make_exactly_what_one_worker_makes(one_worker, tmp_path):
    assert datagen("--out", tmp_path, *ARGS, "--workers", 2) == 0
    _same_shards(one_worker, tmp_path)
    ds = Dataset(tmp_path)
    assert len(ds) == 14 and [ds.shard_count(k) for k in ds.shards] == [8, 6]


def test_an_interrupted_run_resumes_with_the_same_data(one_worker, tmp_path, capsys):
    for f in one_worker.iterdir():
        (tmp_path / f.name).write_bytes(f.read_bytes())
    (tmp_path / "shard-00001.json").unlink()  # died while writing shard 1
    (tmp_path / "shard-00001.npz").rename(tmp_path / "shard-00001.npz.tmp")
    kept = (tmp_path / "shard-00000.npz").stat().st_mtime_ns
    preview = tmp_path / "preview.png"
    assert datagen("--out", tmp_path, *ARGS, "--workers", 1, "--preview", preview) == 0
    assert "6 samples in" in capsys.readouterr().out  # only shard 1 was made again
    assert (tmp_path / "shard-00000.npz").stat().st_mtime_ns == kept
    _same_shards(one_worker, tmp_path)
    picture = cv2.imread(str(preview))
    assert picture is not None and picture.shape[1] > 6 * 256


def test_a_folder_holding_another_data_set_is_refused(one_worker, capsys):
    assert datagen("--out", one_worker, "--count", "14", "--seed", "4", "--shard-size", "8",
                   "--workers", 1) == 2
    assert "holds a different data set" in capsys.readouterr().err
    assert datagen("--out", one_worker, *ARGS, "--hidden-lines", "omit", "--workers", 1) == 2
    assert "holds a different data set" in capsys.readouterr().err


def test_the_manifest_describes_the_set(one_worker):
    ds = Dataset(one_worker)
    m = ds.manifest
    assert (m["count"], m["seed"], m["noise"], m["noise_levels"]) == (14, 3, "1", [1])
    assert m["hidden_lines"] == "draw" and m["regular_share"] == 0.0
    assert m["image_size"] == 256 and m["shards"] == ["shard-00000.npz", "shard-00001.npz"]


def test_a_regular_share_of_0_makes_the_same_bytes_as_no_option(one_worker, tmp_path):
    assert datagen("--out", tmp_path, *ARGS, "--regular-share", 0, "--workers", 1) == 0
    _same_shards(one_worker, tmp_path)


def test_the_manifest_records_the_regular_share_and_a_resume_must_match(tmp_path, capsys):
    args = ["--count", 4, "--seed", 3, "--shard-size", 4, "--workers", 1]
    assert datagen("--out", tmp_path, *args, "--regular-share", 0.5) == 0
    assert Dataset(tmp_path).manifest["regular_share"] == 0.5
    assert datagen("--out", tmp_path, *args) == 2
    assert "holds a different data set" in capsys.readouterr().err
    assert datagen("--out", tmp_path, *args, "--regular-share", 0.5) == 0  # same: resumes
    assert datagen("--out", tmp_path / "bad", *args, "--regular-share", 1.5) == 2
    assert "--regular-share must be between 0 and 1, got 1.5" in capsys.readouterr().err


def test_a_cluster_shard_carries_the_regular_share(tmp_path):
    pool, task = tmp_path / "pool", tmp_path / "task"
    assert datagen("--out", pool, "--count", 4, "--seed", 3, "--shard-size", 4,
                   "--regular-share", 1, "--workers", 1) == 0
    task.mkdir()
    assert make_shard(str(task), 3, "1", "draw", 0, 4, 4, regular_share=1.0) == 0
    _same_shards(pool, task, shards=(0,))


def test_curved_sets_refuse_a_regular_share(tmp_path, capsys):
    assert datagen("--out", tmp_path, "--count", 2, "--curved", "--regular-share", 0.5) == 2
    assert "--regular-share" in capsys.readouterr().err
