# SPDX-License-Identifier: LGPL-2.1-or-later
"""Installed as the Addon Manager installs it: a plain copy of the repository in the Mod
folder of an empty user folder, no dependencies, no setup script. The workbench's own
dialog offers them on first activation; declined, FreeCAD goes on; from the menu
later, they install and the workbench comes up (a real pip install
into the temporary user folder: about a minute from pip's cache)."""

import os
import shutil
import subprocess
from pathlib import Path

import pytest
from freecad_process import PRIME_USER_CONFIG, ROOT, freecad_env, run_script

pytestmark = [pytest.mark.freecad, pytest.mark.gui, pytest.mark.slow]

CHECKS = [
    "loaded_from_the_addon_folder_with_nothing_installed",
    "declined_at_first_activation_freecad_goes_on_and_says_what_to_run",
    "the_install_command_installs_through_the_dialog",
    "the_workbench_is_whole_without_a_restart",
]


def _user_data_dir(env: dict) -> Path:
    out = subprocess.run(
        ["freecadcmd", "-c", "import FreeCAD\nprint('USERDATA=' + FreeCAD.getUserAppDataDir())"],
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
    )
    lines = [ln for ln in out.stdout.splitlines() if ln.startswith("USERDATA=")]
    assert lines, out.stdout + out.stderr
    return Path(lines[-1][len("USERDATA=") :])


def _copy_as_cloned(dest: Path) -> None:
    """The working tree's files as `git clone` would lay them (tracked and new, not ignored)."""
    files = subprocess.run(
        ["git", "ls-files", "-z", "-co", "--exclude-standard"],
        cwd=ROOT,
        capture_output=True,
        check=True,
    ).stdout.split(b"\0")
    for name in filter(None, (f.decode() for f in files)):
        src = ROOT / name
        if src.is_file():
            (dest / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / name)


@pytest.fixture(scope="module")
def addon_run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("addon")
    env = freecad_env(tmp)
    env.update(
        HOME=str(tmp / "home"),
        # pip's cache of the real user, so the wheels need not be downloaded again
        PIP_CACHE_DIR=env.get("PIP_CACHE_DIR", os.path.expanduser("~/.cache/pip")),
        # this machine's registry has the CPU build of torch 2.13.0 (a system torch,
        # as in the chroots, is used instead); users get the CPU index by default
        SKETCH2CAD_TORCH_REQUIREMENT="torch==2.13.0",
        SKETCH2CAD_TORCH_INDEX="",
    )
    for name in ("SKETCH2CAD_DEPENDENCY_FOLDER", "SKETCH2CAD_PYTHON"):
        env.pop(name, None)
    (tmp / "home").mkdir()
    user = _user_data_dir(env)
    _copy_as_cloned(user / "Mod" / "Sketch2CAD")
    subprocess.run(
        ["freecadcmd", "-c", PRIME_USER_CONFIG],
        env=env,
        capture_output=True,
        timeout=120,
        check=True,
    )
    yield run_script("addon_install_session.py", tmp, gui=True, timeout=900, env=env)
    shutil.rmtree(tmp, ignore_errors=True)  # about 2 GB of packages


@pytest.mark.parametrize("name", CHECKS)
def test_addon_install(addon_run, assert_passed, name):
    assert_passed(addon_run, name)


def test_every_check_ran(addon_run, assert_all_ran):
    assert_all_ran(addon_run, CHECKS)
