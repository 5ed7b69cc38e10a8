# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad datagen --ray`: shards as Ray tasks on a local cluster make the process
pool's bytes, survive a killed worker, and resume; without Ray the error says how to
install it."""

import json
import os
import signal
import sys
import threading
import time
from pathlib import Path

from Sketch2CADWorkbench.cli import main

ARGS = ["--count", "14", "--seed", "3", "--shard-size", "8"]  # shards of 8 and 6 samples
SHARDS = [f"shard-0000{k}.{ext}" for k in (0, 1) for ext in ("npz", "json")]


def datagen(*args) -> int:
    return main(["datagen", *map(str, args)])


def _kill_first_shard_task(killed: list, stop: threading.Event) -> None:
    """SIGKILL the first Ray worker seen running a shard task (its process title)."""
    while not stop.is_set():
        for pid in (p for p in os.listdir("/proc") if p.isdigit()):
            try:
                title = Path(f"/proc/{pid}/cmdline").read_bytes()
            except OSError:
                continue
            if title.startswith(b"ray::make_shard"):
                os.kill(int(pid), signal.SIGKILL)
                killed.append(int(pid))
                return
        time.sleep(0.05)


def test_ray_tasks_make_the_pools_bytes_after_a_killed_worker_and_resume(tmp_path, capsys):
    assert datagen("--out", tmp_path / "pool", *ARGS, "--workers", 1) == 0
    killed, stop = [], threading.Event()
    killer = threading.Thread(target=_kill_first_shard_task, args=(killed, stop))
    killer.start()
    try:
        assert datagen("--out", tmp_path / "ray", *ARGS, "--workers", 2, "--ray") == 0
    finally:
        stop.set()
        killer.join()
    assert len(killed) == 1  # a worker died mid-shard; Ray ran its task again
    for name in SHARDS:
        assert (tmp_path / "ray" / name).read_bytes() == (tmp_path / "pool" / name).read_bytes()
    manifest = json.loads((tmp_path / "ray" / "manifest.json").read_text())
    assert manifest == json.loads((tmp_path / "pool" / "manifest.json").read_text())
    assert manifest["complete"] == [0, 1]

    (tmp_path / "ray" / "shard-00001.json").unlink()  # shard 1 lost: made again, alone
    kept = (tmp_path / "ray" / "shard-00000.npz").stat().st_mtime_ns
    capsys.readouterr()
    assert datagen("--out", tmp_path / "ray", *ARGS, "--workers", 2, "--ray") == 0
    assert "6 samples in" in capsys.readouterr().out
    assert (tmp_path / "ray" / "shard-00000.npz").stat().st_mtime_ns == kept
    assert (tmp_path / "ray" / "shard-00001.json").read_bytes() == (
        tmp_path / "pool" / "shard-00001.json"
    ).read_bytes()


def test_without_ray_the_error_says_how_to_install_it(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "ray", None)  # import ray raises ImportError
    assert datagen("--out", tmp_path / "set", *ARGS, "--ray") == 2
    assert "optional extra 'cluster'" in capsys.readouterr().err
    assert not (tmp_path / "set").exists()  # nothing written
