# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad interpret` never writes over the session it reads (the user's sketches)."""
import shutil
import subprocess
import sys
from pathlib import Path

CLI = [sys.executable, "-m", "Sketch2CADWorkbench.cli"]
SESSION = Path(__file__).resolve().parents[2] / "examples" / "sessions" / "camera.json"


def test_an_output_on_the_session_is_refused_and_the_session_kept(tmp_path):
    s = tmp_path / "s.json"
    shutil.copy(SESSION, s)
    before = s.read_bytes()
    for option in ("--protocol", "--step", "--png"):
        out = subprocess.run([*CLI, "interpret", str(s), option, str(s)], capture_output=True,
                             text=True, timeout=120)
        assert out.returncode == 2 and "same file as SESSION" in out.stderr, out.stderr
        assert s.read_bytes() == before
    out = subprocess.run([*CLI, "interpret", str(s), "--protocol", str(tmp_path / "x"),
                          "--step", str(tmp_path / "x")], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 2 and "--step" in out.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.json"]
