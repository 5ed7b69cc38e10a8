# SPDX-License-Identifier: LGPL-2.1-or-later
"""Atomic writes (brep/files.py): readers never see a part of a file, writers never share
a temporary, failures replace nothing, modes are kept, stale temporaries are cleaned."""

import json
import os
import subprocess
import sys
import textwrap
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
