# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad datagen`: the same data with any worker count, resumable, with a preview;
a killed worker is replaced, a killed main process takes its workers with it, and bad
input is refused saying why."""

import contextlib
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

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
    assert (
        datagen(
            "--out", one_worker, "--count", "14", "--seed", "4", "--shard-size", "8", "--workers", 1
        )
        == 2
    )
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


def test_people_s_hand_is_its_own_set_and_a_cluster_shard_carries_it(tmp_path, capsys):
    args = ["--count", 4, "--seed", 3, "--shard-size", 4, "--workers", 1]
    assert datagen("--out", tmp_path / "people", *args, "--hand", "people") == 0
    people = Dataset(tmp_path / "people")
    assert people.manifest["hand"] == "people"
    assert datagen("--out", tmp_path / "people", *args) == 2  # another hand: not a resume
    assert "holds a different data set" in capsys.readouterr().err
    assert datagen("--out", tmp_path / "generator", *args) == 0
    drawn = [
        [s.strokes for s in Dataset(tmp_path / hand).samples(0)] for hand in ("people", "generator")
    ]
    assert not all(
        len(a) == len(b) and all(np.array_equal(x, y) for x, y in zip(a, b, strict=False))
        for a, b in zip(*drawn, strict=False)
    )
    task = tmp_path / "task"
    task.mkdir()
    assert make_shard(str(task), 3, "1", "draw", 0, 4, 4, hand="people") == 0
    _same_shards(tmp_path / "people", task, shards=(0,))


def test_a_cluster_shard_carries_the_regular_share(tmp_path):
    pool, task = tmp_path / "pool", tmp_path / "task"
    assert (
        datagen(
            "--out",
            pool,
            "--count",
            4,
            "--seed",
            3,
            "--shard-size",
            4,
            "--regular-share",
            1,
            "--workers",
            1,
        )
        == 0
    )
    task.mkdir()
    assert make_shard(str(task), 3, "1", "draw", 0, 4, 4, regular_share=1.0) == 0
    _same_shards(pool, task, shards=(0,))


def test_curved_sets_refuse_a_regular_share(tmp_path, capsys):
    assert datagen("--out", tmp_path, "--count", 2, "--curved", "--regular-share", 0.5) == 2
    assert "--regular-share" in capsys.readouterr().err


@pytest.mark.parametrize("make", ["file", "dangling link", "file as parent"])
def test_an_out_that_cannot_be_a_folder_is_refused_saying_why(tmp_path, capsys, make):
    target = tmp_path / "set"
    if make == "file":
        target.write_text("notes")
    elif make == "dangling link":
        target.symlink_to(tmp_path / "gone")
    else:
        (tmp_path / "notes").write_text("notes")
        target = tmp_path / "notes" / "set"
    assert datagen("--out", target, *ARGS, "--workers", 1) == 2
    err = capsys.readouterr().err
    assert f"--out {target}" in err
    assert ("which does not exist" if make == "dangling link" else "is not a folder") in err
    assert not (tmp_path / "gone").exists()
    if make != "dangling link":
        assert (tmp_path / ("set" if make == "file" else "notes")).read_text() == "notes"


def _kill_pool_workers(killed: list, stop: threading.Event, every: bool) -> None:
    """SIGKILL this process's pool workers (spawned children) as they are seen: the
    first one only, or every one until `stop`."""
    me = str(os.getpid())
    while not stop.is_set():
        for pid in (p for p in os.listdir("/proc") if p.isdigit() and int(p) not in killed):
            try:
                ppid = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[1]
                title = Path(f"/proc/{pid}/cmdline").read_bytes()
            except OSError:
                continue
            if ppid == me and b"spawn_main" in title:
                os.kill(int(pid), signal.SIGKILL)
                killed.append(int(pid))
                if not every:
                    return
        time.sleep(0.05)


@contextlib.contextmanager
def killing_pool_workers(every: bool):
    killed, stop = [], threading.Event()
    killer = threading.Thread(target=_kill_pool_workers, args=(killed, stop, every))
    killer.start()
    try:
        yield killed
    finally:
        stop.set()
        killer.join()


def test_a_killed_worker_is_replaced_and_the_data_is_the_same(one_worker, tmp_path):
    with killing_pool_workers(every=False) as killed:
        assert datagen("--out", tmp_path, *ARGS, "--workers", 2) == 0
    assert len(killed) == 1
    _same_shards(one_worker, tmp_path)


def test_workers_that_keep_dying_stop_the_run_with_the_reason_keeping_shards_written(
    one_worker, tmp_path, capsys
):
    for f in one_worker.iterdir():  # shard 0 written by an earlier run; shard 1 to make
        if f.name != "manifest.json" and not f.name.startswith("shard-00001"):
            (tmp_path / f.name).write_bytes(f.read_bytes())
    kept = (tmp_path / "shard-00000.npz").stat().st_mtime_ns
    with killing_pool_workers(every=True) as killed:
        assert datagen("--out", tmp_path, *ARGS, "--workers", 2) == 2
    assert len(killed) >= 2  # the pool was started afresh once
    err = capsys.readouterr().err
    assert "a worker process died twice" in err and "the 1 shard(s) written are kept" in err
    assert (tmp_path / "shard-00000.npz").stat().st_mtime_ns == kept
    assert Dataset(tmp_path).manifest["complete"] == [0]
    assert datagen("--out", tmp_path, *ARGS, "--workers", 2) == 0  # the same command finishes
    _same_shards(one_worker, tmp_path)


def _children(pid: int) -> dict[int, bytes]:
    """The live child processes of `pid`, with their command lines."""
    out = {}
    for p in (p for p in os.listdir("/proc") if p.isdigit()):
        try:
            stat = Path(f"/proc/{p}/stat").read_text().rsplit(")", 1)[1].split()
            title = Path(f"/proc/{p}/cmdline").read_bytes()
        except OSError:
            continue
        if stat[1] == str(pid) and stat[0] != "Z":
            out[int(p)] = title
    return out


def _alive(pid: int) -> bool:
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def test_the_workers_and_resource_tracker_exit_when_the_main_process_is_killed(tmp_path):
    cmd = [sys.executable, "-m", "Sketch2CADWorkbench.cli", "datagen", "--out", str(tmp_path)]
    main_process = subprocess.Popen(
        [*cmd, "--count", "400", "--seed", "3", "--workers", "2"], stderr=subprocess.DEVNULL
    )
    deadline = time.monotonic() + 120
    try:
        while True:
            kids = _children(main_process.pid)
            workers = [p for p, title in kids.items() if b"spawn_main" in title]
            if len(workers) == 2 and any(b"resource_tracker" in t for t in kids.values()):
                break
            assert main_process.poll() is None and time.monotonic() < deadline, kids
            time.sleep(0.1)
    finally:
        main_process.kill()
        main_process.wait()
    deadline = time.monotonic() + 90  # a worker still importing exits once it is done
    while any(_alive(p) for p in kids) and time.monotonic() < deadline:
        time.sleep(0.2)
    left = {p: t[:80] for p, t in kids.items() if _alive(p)}
    for p in left:
        os.kill(p, signal.SIGKILL)
    assert not left


def test_a_round_share_of_0_makes_the_same_bytes_and_manifest_as_no_option(one_worker, tmp_path):
    assert datagen("--out", tmp_path, *ARGS, "--round-share", 0, "--workers", 1) == 0
    _same_shards(one_worker, tmp_path)
    assert (tmp_path / "manifest.json").read_bytes() == (one_worker / "manifest.json").read_bytes()


def test_the_manifest_records_a_round_share_and_a_resume_must_match(tmp_path, capsys):
    args = ["--count", 4, "--seed", 3, "--shard-size", 4, "--workers", 1]
    assert datagen("--out", tmp_path, *args, "--round-share", 0.5) == 0
    assert Dataset(tmp_path).manifest["round_share"] == 0.5
    assert datagen("--out", tmp_path, *args) == 2
    assert "holds a different data set" in capsys.readouterr().err
    assert datagen("--out", tmp_path / "bad", *args, "--round-share", -0.1) == 2
    assert "--round-share must be between 0 and 1, got -0.1" in capsys.readouterr().err
