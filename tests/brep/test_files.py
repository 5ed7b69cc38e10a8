# SPDX-License-Identifier: LGPL-2.1-or-later
"""Atomic writes (brep/files.py): readers never see a part of a file, writers never share
a temporary, failures replace nothing, modes are kept, stale temporaries are cleaned;
devices and FIFOs are written into, links followed, errors name the given path; inputs
are read up to a cap."""

import errno
import json
import os
import stat
import subprocess
import sys
import textwrap
import threading
import time

import pytest

from Sketch2CADWorkbench.brep import files


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path):
    path = tmp_path / "p.json"
    path.write_text("old")
    with pytest.raises(RuntimeError), files.atomic_path(path) as tmp:
        tmp.write_text("half")
        raise RuntimeError("the writer failed")
    assert path.read_text() == "old" and os.listdir(tmp_path) == ["p.json"]


def test_outputs_are_replaced_all_or_none(tmp_path):
    a, b = tmp_path / "a.step", tmp_path / "b.png"
    a.write_text("old a")
    with pytest.raises(OSError), files.atomic_outputs([a, b]) as (ta, tb):
        ta.write_text("new a")  # b's writer writes nothing: an error, as OCCT's can
    assert a.read_text() == "old a" and not b.exists()
    assert sorted(os.listdir(tmp_path)) == ["a.step"]
    with files.atomic_outputs([a, b]) as (ta, tb):
        ta.write_text("new a")
        tb.write_text("new b")
    assert (a.read_text(), b.read_text()) == ("new a", "new b")


def test_the_mode_of_a_replaced_file_is_kept_and_a_new_one_gets_the_umasks(tmp_path):
    old = tmp_path / "old.json"
    old.write_text("x")
    old.chmod(0o640)
    files.write_atomically(old, "y")
    assert old.stat().st_mode & 0o777 == 0o640
    umask = os.umask(0o022)
    try:
        files.write_atomically(tmp_path / "new.json", "z")
    finally:
        os.umask(umask)
    assert (tmp_path / "new.json").stat().st_mode & 0o777 == 0o644


def test_temporaries_keep_the_suffix_and_differ_per_writer(tmp_path):
    a, b = files.temporary_path(tmp_path / "x.step"), files.temporary_path(tmp_path / "x.step")
    assert a != b and a.suffix == b.suffix == ".step" and a.parent == tmp_path
    assert a.name.startswith(".x.step" + files.MARK)


def test_a_temporary_of_a_killed_writer_is_removed_by_the_next_write(tmp_path):
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    stale = tmp_path / f".p.json{files.MARK}{dead.pid}-deadbeef.json"
    stale.write_text("")
    live = tmp_path / f".p.json{files.MARK}{os.getpid()}-cafef00d.json"
    live.write_text("")  # this process's own: still being written
    files.write_atomically(tmp_path / "p.json", "{}")
    assert not stale.exists() and live.exists()


WRITER = textwrap.dedent("""
    import json, sys
    from Sketch2CADWorkbench.brep.files import write_atomically
    for i in range(int(sys.argv[2])):
        write_atomically(sys.argv[1], json.dumps({"writer": sys.argv[3], "i": i,
                                                  "pad": "x" * 200000}))
""")


def test_two_writers_of_one_path_never_leave_a_reader_a_broken_file(tmp_path):
    path = tmp_path / "shared.json"
    files.write_atomically(path, json.dumps({"writer": "start"}))
    writers = [
        subprocess.Popen(
            [sys.executable, "-c", WRITER, str(path), "150", name],
            stderr=subprocess.PIPE,
            text=True,
        )
        for name in "ab"
    ]
    reads, broken, deadline = 0, 0, time.monotonic() + 120
    while any(w.poll() is None for w in writers) and time.monotonic() < deadline:
        try:
            json.loads(path.read_text())
        except ValueError:
            broken += 1
        reads += 1
    errors = [w.communicate()[1] for w in writers]
    assert all(w.returncode == 0 for w in writers), errors
    assert reads > 0 and broken == 0, (reads, broken)
    assert os.listdir(tmp_path) == ["shared.json"]


def test_an_output_on_an_input_or_on_another_output_is_refused():
    with pytest.raises(ValueError, match=r"--step p.json is the same file as PROTOCOL"):
        files.check_outputs({"PROTOCOL": "p.json"}, {"--step": "p.json", "--png": None})
    with pytest.raises(ValueError, match=r"--png ./x is the same file as --step"):
        files.check_outputs({"PROTOCOL": "p.json"}, {"--step": "x", "--png": "./x"})
    files.check_outputs({"PROTOCOL": "p.json"}, {"--step": "p.step", "--png": None})


def test_a_device_is_written_into_not_replaced(tmp_path, memory_device):
    null = memory_device(tmp_path / "null", 3)
    files.write_atomically(null, "discarded")
    assert stat.S_ISCHR(null.stat().st_mode)
    assert sorted(os.listdir(tmp_path)) == ["null"]


def test_a_full_disk_is_reported_as_one_naming_the_path(tmp_path, memory_device):
    full = memory_device(tmp_path / "full", 7)  # every write: ENOSPC
    with pytest.raises(OSError, match=f"{full}: the disk is full") as e:
        files.write_atomically(full, "x" * 100000)
    assert e.value.errno == errno.ENOSPC and files.MARK not in str(e.value)
    assert stat.S_ISCHR(full.stat().st_mode)


def test_a_fifo_gets_the_bytes_and_stays_a_fifo(tmp_path):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    got = []
    reader = threading.Thread(target=lambda: got.append(fifo.read_bytes()), daemon=True)
    reader.start()
    files.write_atomically(fifo, b"through the pipe")
    reader.join(10)
    assert got == [b"through the pipe"] and stat.S_ISFIFO(fifo.stat().st_mode)


def test_a_link_stays_a_link_and_its_target_is_written(tmp_path):
    (tmp_path / "real").mkdir()
    target = tmp_path / "real" / "model.step"
    target.write_text("old")
    target.chmod(0o640)
    link = tmp_path / "link.step"
    link.symlink_to("real/model.step")
    files.write_atomically(link, "new")
    assert link.is_symlink() and os.readlink(link) == "real/model.step"
    assert target.read_text() == "new" and target.stat().st_mode & 0o777 == 0o640
    assert os.listdir(tmp_path / "real") == ["model.step"]


def test_a_dangling_link_gets_its_target_made(tmp_path):
    link = tmp_path / "link.json"
    link.symlink_to(tmp_path / "later.json")
    files.write_atomically(link, "{}")
    assert link.is_symlink() and (tmp_path / "later.json").read_text() == "{}"


def test_a_link_to_a_process_descriptor_is_written_into(tmp_path):
    out = tmp_path / "out.txt"
    code = textwrap.dedent("""
        import os, sys
        from Sketch2CADWorkbench.brep.files import write_atomically
        os.symlink("/proc/self/fd/1", sys.argv[1])  # as /dev/stdout is
        print("before", flush=True)
        write_atomically(sys.argv[1], "written\\n")
        print("after", flush=True)
    """)
    with open(out, "w") as f:
        done = subprocess.run([sys.executable, "-c", code, str(tmp_path / "stdout")], stdout=f)
    assert done.returncode == 0
    assert out.read_text() == "before\nwritten\nafter\n"
    assert (tmp_path / "stdout").is_symlink()


def test_a_folder_is_refused_as_an_output(tmp_path):
    with pytest.raises(IsADirectoryError, match="is a folder"):
        files.write_atomically(tmp_path, "x")
    with pytest.raises(ValueError, match=r"--step .* is a folder"):
        files.check_outputs({}, {"--step": tmp_path})


def test_a_write_error_names_the_given_path_not_the_temporary(tmp_path):
    blocked = tmp_path / "a-file"
    blocked.write_text("")
    with pytest.raises(OSError) as e:
        files.write_atomically(blocked / "x.step", "x")
    assert str(blocked / "x.step") in str(e.value) and files.MARK not in str(e.value)


def test_an_input_past_the_cap_is_refused_before_it_is_read(tmp_path, monkeypatch, memory_device):
    big = tmp_path / "big.json"
    big.write_bytes(b" " * 3000)
    monkeypatch.setenv(files.MAX_INPUT_ENV, "0.002")
    with pytest.raises(OSError, match=f"larger than 0.002 MB.*set {files.MAX_INPUT_ENV}"):
        files.read_capped(big)
    monkeypatch.setenv(files.MAX_INPUT_ENV, "0.004")
    assert len(files.read_capped(big)) == 3000
    monkeypatch.setenv(files.MAX_INPUT_ENV, "lots")
    with pytest.raises(ValueError, match=files.MAX_INPUT_ENV):
        files.read_capped(big)
    monkeypatch.delenv(files.MAX_INPUT_ENV)
    zero = memory_device(tmp_path / "zero", 5)  # endless zeros, as /dev/zero
    with pytest.raises(OSError, match="larger than 64 MB"):
        files.read_capped(zero)
