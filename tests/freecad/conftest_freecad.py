# SPDX-License-Identifier: LGPL-2.1-or-later
"""Running scripts inside FreeCAD (freecadcmd, or the GUI under Xvfb)."""
import os
import shutil
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = Path(__file__).resolve().parent / "scripts"


def freecad_env(tmp_path, **extra) -> dict:
    env = dict(os.environ, LANG="C.UTF-8", SKETCH2CAD_ROOT=str(ROOT),
               SKETCH2CAD_TMP=str(tmp_path), QTWEBENGINE_CHROMIUM_FLAGS="--no-sandbox",
               QTWEBENGINE_DISABLE_SANDBOX="1", **extra)
    env.pop("PYTHONPATH", None)
    return env


def run_freecadcmd(script: str, tmp_path, timeout: int = 300, **extra):
    """Run tests/freecad/scripts/<script> in freecadcmd; returns the CompletedProcess."""
    exe = shutil.which("freecadcmd")
    assert exe, "freecadcmd is not installed (scripts/setup.sh installs it)"
    return subprocess.run([exe, str(SCRIPTS / script)], capture_output=True, text=True,
                          timeout=timeout, env=freecad_env(tmp_path, **extra), cwd=tmp_path)


def run_freecad_gui(script: str, tmp_path, timeout: int = 300, **extra):
    """Run a script in FreeCAD's GUI on a virtual X screen."""
    for exe in ("xvfb-run", "freecad"):
        assert shutil.which(exe), f"{exe} is not installed (scripts/setup.sh installs it)"
    return subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", "freecad",
                           str(SCRIPTS / script)], capture_output=True, text=True,
                          timeout=timeout, env=freecad_env(tmp_path, **extra), cwd=tmp_path)
