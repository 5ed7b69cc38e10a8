# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad build` writes STEP for a good protocol and a clear error for a bad one."""

import json
import os
import shutil
import stat
import subprocess
import sys
import time

import pytest

from Sketch2CADWorkbench.brep import files
from Sketch2CADWorkbench.brep.exchange import import_step
from Sketch2CADWorkbench.brep.operators import build
from Sketch2CADWorkbench.brep.protocol import load

CLI = [sys.executable, "-m", "Sketch2CADWorkbench.cli"]  # the interpreter pytest runs in


def run(*args):
    return subprocess.run([*CLI, *map(str, args)], capture_output=True, text=True, timeout=120)


def test_build_writes_step_with_the_protocol_volume(tmp_path, examples_dir):
    out = run("build", examples_dir / "hammer.json", "--step", tmp_path / "h.step")
    assert out.returncode == 0, out.stderr
    assert "Extrude" in out.stdout  # the listing is printed
    expected = build(load(examples_dir / "hammer.json")).Volume()
    assert import_step(tmp_path / "h.step").Volume() == pytest.approx(expected, rel=1e-6)


def test_bad_protocol_fails_with_the_field_and_writes_nothing(tmp_path, examples_dir):
    bad = json.loads((examples_dir / "nut.json").read_text())
    bad["operations"][1]["r0"] = -1
    (tmp_path / "bad.json").write_text(json.dumps(bad))
    out = run("build", tmp_path / "bad.json", "--step", tmp_path / "bad.step")
    assert out.returncode == 2
    assert "operations[1].r0: expected a positive number, got -1" in out.stderr
    assert not (tmp_path / "bad.step").exists()


def test_unbuildable_step_keeps_an_existing_output_file(tmp_path, examples_dir):
    p = json.loads((examples_dir / "nut.json").read_text())
    p["operations"][2]["d"] = -500.0  # pocket far through the nut
    (tmp_path / "p.json").write_text(json.dumps(p))
    shutil.copy(examples_dir / "nut.json", tmp_path / "keep.step")
    out = run("build", tmp_path / "p.json", "--step", tmp_path / "keep.step")
    assert out.returncode == 2 and "step 3 (extrude)" in out.stderr
    assert (tmp_path / "keep.step").read_text() == (examples_dir / "nut.json").read_text()


def test_an_output_that_is_the_protocol_is_refused_and_the_protocol_kept(tmp_path, examples_dir):
    p = tmp_path / "p.json"
    shutil.copy(examples_dir / "nut.json", p)
    before = p.read_bytes()
    for option in ("--step", "--png"):
        out = run("build", p, option, p)
        assert out.returncode == 2 and "same file as PROTOCOL" in out.stderr, out.stderr
        assert p.read_bytes() == before


def test_two_outputs_on_one_path_are_refused_before_any_work(tmp_path, examples_dir):
    out = run("build", examples_dir / "nut.json", "--step", tmp_path / "x", "--png", tmp_path / "x")
    assert out.returncode == 2 and "--png" in out.stderr and "--step" in out.stderr
    assert not (tmp_path / "x").exists()


def test_an_output_that_cannot_be_written_replaces_no_other(tmp_path, examples_dir):
    step = tmp_path / "out.step"
    step.write_text("the previous export")
    blocked = tmp_path / "not-a-folder"
    blocked.write_text("a file where the picture's folder would be")
    out = run("build", examples_dir / "nut.json", "--step", step, "--png", blocked / "x.png")
    assert out.returncode == 2, out.stdout
    assert step.read_text() == "the previous export"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["not-a-folder", "out.step"]


def test_a_replaced_output_keeps_its_mode(tmp_path, examples_dir):
    step = tmp_path / "out.step"
    step.write_text("old")
    step.chmod(0o644)
    assert run("build", examples_dir / "nut.json", "--step", step).returncode == 0
    assert step.stat().st_mode & 0o777 == 0o644
    assert "ISO-10303-21" in step.read_text()[:100]


def test_a_device_output_is_written_into_and_stays_a_device(tmp_path, examples_dir, memory_device):
    null = memory_device(tmp_path / "null", 3)  # as /dev/null
    out = run("build", examples_dir / "nut.json", "--step", null, "--quiet")
    assert out.returncode == 0, out.stderr
    assert stat.S_ISCHR(null.stat().st_mode) and os.listdir(tmp_path) == ["null"]


def test_a_picture_without_an_extension_is_still_a_png(tmp_path, examples_dir):
    args = ["build", str(examples_dir / "nut.json"), "--png", "noext", "--quiet"]
    out = subprocess.run([*CLI, *args], capture_output=True, text=True, cwd=tmp_path, timeout=120)
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "noext").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_an_empty_output_path_is_refused_naming_the_option(tmp_path, examples_dir):
    out = run("build", examples_dir / "nut.json", "--step", "")
    assert out.returncode == 2 and "--step: an empty path" in out.stderr, out.stderr
    assert "PosixPath" not in out.stderr


def test_an_endless_input_is_refused_at_the_cap(tmp_path, memory_device):
    zero = memory_device(tmp_path / "zero", 5)  # as /dev/zero
    out = run("build", zero)
    assert out.returncode == 2
    assert "larger than 64 MB" in out.stderr and "SKETCH2CAD_MAX_INPUT_MB" in out.stderr


# A build that stops for good just before it moves its output into place.
STALLED = (
    "import os, sys, time; os.replace = lambda *a: time.sleep(600); "
    "from Sketch2CADWorkbench.cli import main; sys.exit(main(sys.argv[1:]))"
)


def test_the_temporaries_of_a_killed_build_are_removed_by_the_next(tmp_path, examples_dir):
    step = tmp_path / "out.step"
    args = ["build", str(examples_dir / "nut.json"), "--step", str(step), "--quiet"]
    stalled = subprocess.Popen([sys.executable, "-c", STALLED, *args])
    deadline = time.monotonic() + 120
    while not any(files.MARK in p.name for p in tmp_path.iterdir()):
        assert stalled.poll() is None and time.monotonic() < deadline
        time.sleep(0.2)
    time.sleep(1.0)  # the writing done, the move never comes
    stalled.kill()
    stalled.wait()
    assert run(*args).returncode == 0
    assert os.listdir(tmp_path) == ["out.step"]


def holes(steps):
    """A plate with `steps` small square holes in its top."""
    from Sketch2CADWorkbench.brep.protocol import AddSubPrism, Box, FaceRef, Mode, Protocol

    top = FaceRef((0.0, 0.0, 5.0), (0.0, 0.0, 1.0))
    ops = tuple(
        AddSubPrism(
            top,
            tuple((x + dx, y + dy, 5.0) for dx, dy in ((-1, -1), (1, -1), (1, 1), (-1, 1))),
            2.0,
            Mode.SUBTRACT,
        )
        for x, y in ((-45.0 + 10 * (i % 10), -45.0 + 10 * (i // 10)) for i in range(steps))
    )
    return Protocol(Box((100.0, 100.0, 10.0)), ops)


@pytest.mark.parametrize(
    "terminal, steps, shown",
    [(True, 2, True), (False, 2, False), (False, "PROGRESS_FROM", True)],
)
def test_a_replay_shows_its_progress_on_a_terminal_or_when_it_is_long(
    tmp_path, stderr_of, terminal, steps, shown
):
    from Sketch2CADWorkbench.cli import main
    from Sketch2CADWorkbench.cli.build import PROGRESS_FROM

    steps = PROGRESS_FROM if steps == "PROGRESS_FROM" else steps
    holes(steps).save(tmp_path / "plate.json")
    err = stderr_of(terminal)
    assert main(["build", str(tmp_path / "plate.json"), "--quiet"]) == 0
    assert ("build plate.json" in err.getvalue()) == shown, err.getvalue()
    if shown:
        assert f"/{steps} [" in err.getvalue()  # tqdm's count of the steps


def test_an_output_under_a_file_is_refused_naming_both(tmp_path, examples_dir):
    shutil.copy(examples_dir / "nut.json", tmp_path / "p.json")
    before = (tmp_path / "p.json").read_bytes()
    out = run("build", tmp_path / "p.json", "--step", tmp_path / "p.json" / "x.step")
    assert out.returncode == 2
    assert f"{tmp_path / 'p.json' / 'x.step'}: cannot make its folder: " in out.stderr
    assert f"{tmp_path / 'p.json'} is a file, not a folder" in out.stderr, out.stderr
    assert (tmp_path / "p.json").read_bytes() == before
