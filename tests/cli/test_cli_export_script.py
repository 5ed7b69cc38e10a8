# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad export-script` writes a CadQuery or build123d script; `build --fcstd` needs
FreeCAD and says so without it."""

import os
import subprocess
import sys

CLI = [sys.executable, "-m", "Sketch2CADWorkbench.cli"]


def run(*args, env=None):
    return subprocess.run(
        [*CLI, *map(str, args)], capture_output=True, text=True, timeout=300, env=env
    )


def test_export_script_writes_a_script_with_a_block_per_step(tmp_path, examples_dir):
    out = run("export-script", examples_dir / "nut.json", "--cadquery", tmp_path / "nut.py")
    assert out.returncode == 0, out.stderr
    text = (tmp_path / "nut.py").read_text()
    compile(text, "nut.py", "exec")
    assert text.count("# Step ") == 6 and "import cadquery as cq" in text
    assert "Sketch2CADWorkbench" not in text


def test_export_script_writes_both_libraries_scripts_at_once(tmp_path, examples_dir):
    out = run(
        "export-script",
        examples_dir / "lamp.json",
        "--cadquery",
        tmp_path / "cq.py",
        "--build123d",
        tmp_path / "b3d.py",
    )
    assert out.returncode == 0, out.stderr
    cq_text, b3d_text = ((tmp_path / n).read_text() for n in ("cq.py", "b3d.py"))
    assert "from build123d import *" in b3d_text and "import cadquery" not in b3d_text
    assert cq_text.count("# Step ") == b3d_text.count("# Step ") == 8


def test_export_script_without_a_library_says_which_to_give(examples_dir):
    out = run("export-script", examples_dir / "nut.json")
    assert out.returncode == 2
    assert "--cadquery or --build123d" in out.stderr


def test_export_script_refuses_to_overwrite_its_protocol(tmp_path, examples_dir):
    target = tmp_path / "nut.json"
    target.write_text((examples_dir / "nut.json").read_text())
    out = run("export-script", target, "--cadquery", target)
    assert out.returncode == 2 and "--cadquery" in out.stderr
    assert target.read_text() == (examples_dir / "nut.json").read_text()


def test_build_fcstd_without_freecad_says_so_and_writes_nothing(tmp_path, examples_dir):
    env = dict(os.environ, PATH=str(tmp_path), SKETCH2CAD_FREECADCMD="")
    out = run("build", examples_dir / "nut.json", "--fcstd", tmp_path / "n.FCStd", env=env)
    assert out.returncode == 2
    assert "--fcstd needs FreeCAD" in out.stderr
    assert not (tmp_path / "n.FCStd").exists()
