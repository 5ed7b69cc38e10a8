# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad build` writes STEP for a good protocol and a clear error for a bad one."""
import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

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
