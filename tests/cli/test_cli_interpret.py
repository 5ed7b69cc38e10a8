# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad interpret` never writes over the session it reads (the user's sketches), and
replays each step with the choices saved in it."""
import json
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


def test_the_replay_keeps_the_snaps_a_step_undid_undone_and_its_grid(tmp_path):
    # hammer's first step (a sweep) snaps its position to the face's centre line; the
    # Sketch panel's "Undo snap" saves skip_snaps in the step, and a replay honours it
    session = json.loads(SESSION.with_name("hammer.json").read_text())
    session["steps"] = session["steps"][:1]
    choices = session["steps"][0]["choices"]
    choices.update(regularize=True, snap_step=1.0)
    outputs = []
    for skip in ([], ["position"]):
        choices["skip_snaps"] = skip
        (tmp_path / "s.json").write_text(json.dumps(session))
        out = subprocess.run([*CLI, "interpret", str(tmp_path / "s.json")], capture_output=True,
                             text=True, timeout=600)
        assert out.returncode == 0, out.stderr
        outputs.append(out.stdout)
    assert "position snapped" in outputs[0] and "position snapped" not in outputs[1]
    assert all("snapped to the 1 mm grid" in o for o in outputs)
