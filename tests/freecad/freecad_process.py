# SPDX-License-Identifier: LGPL-2.1-or-later
"""Running scripts inside FreeCAD: freecadcmd, or the GUI on a virtual X screen (used by
conftest.py's fixtures and by tests that set up a user folder of their own).

The scripts in scripts/ print "CHECK PASSED <name>" or "CHECK FAILED <name>" with a
traceback for each check, and exit 1 if any failed (freecadcmd would exit 0 on an
uncaught exception).
"""

import os
import shutil
import signal
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = Path(__file__).resolve().parent / "scripts"
XVFB = ["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24"]


def freecad_env(tmp_path) -> dict:
    env = dict(
        os.environ,
        LANG="C.UTF-8",
        SKETCH2CAD_ROOT=str(ROOT),
        SKETCH2CAD_TMP=str(tmp_path),
        # as root, the Start page's web view needs these or FreeCAD exits
        QTWEBENGINE_CHROMIUM_FLAGS="--no-sandbox",
        QTWEBENGINE_DISABLE_SANDBOX="1",
        # FreeCAD keeps its documents' recovery files in its cache folder: one killed with
        # a document open (by a test's timeout, or any crash) leaves them, and the next
        # FreeCAD to start there opens the modal Document Recovery dialog, which takes every
        # mouse event from the window. Each run has a cache of its own.
        XDG_CACHE_HOME=str(Path(tmp_path) / "cache"),
    )
    env.pop("PYTHONPATH", None)  # FreeCAD's own path set-up, as a user would have it
    return env


def run_script(
    script: str, tmp_path, gui: bool, timeout: int, env: dict | None = None
) -> subprocess.CompletedProcess:
    """Run the script (in `env`, default `_env(tmp_path)`); past `timeout` seconds FreeCAD
    (and Xvfb) are killed, and the output so far comes back with return code -9."""
    exe = "freecad" if gui else "freecadcmd"
    for tool in [exe] + (XVFB[:1] if gui else []):
        assert shutil.which(tool), f"{tool} is not installed (scripts/setup.sh installs it)"
    cmd = (XVFB if gui else []) + [exe, str(SCRIPTS / script)]
    proc = subprocess.Popen(
        cmd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env or freecad_env(tmp_path),
        cwd=tmp_path,
        start_new_session=True,
    )
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)  # its own session: xvfb-run, Xvfb and FreeCAD
        out, err = proc.communicate()
        err += f"\n{script} killed after {timeout} s"
    return subprocess.CompletedProcess(cmd, proc.returncode, out, err)


def print_figures(out: subprocess.CompletedProcess) -> None:
    """Print the script's "FIGURE <name> <value>" lines (shown with pytest -s)."""
    print("".join(f"\n{line}" for line in out.stdout.splitlines() if line.startswith("FIGURE ")))


# FreeCAD 1.0 moves its old Start workbench's settings on the first start of a user config
# and says so in the report view; the checks' processes end by os._exit, which never saves
# that it is done. A user's config has done it once: so does the test's, before the GUI runs.
PRIME_USER_CONFIG = (
    "import FreeCAD\n"
    "FreeCAD.ParamGet('User parameter:BaseApp/Preferences/Mod/Start')"
    ".SetBool('Migration2024Complete', True)\n"
    "FreeCAD.saveParameter()\n"
)
