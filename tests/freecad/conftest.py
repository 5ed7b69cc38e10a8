# SPDX-License-Identifier: LGPL-2.1-or-later
"""Fixtures running scripts inside FreeCAD (see freecad_process.py)."""

import subprocess

import pytest
from freecad_process import PRIME_USER_CONFIG, freecad_env, run_script


@pytest.fixture(scope="session")
def run_freecad(tmp_path_factory):
    """run_freecad(script, tmp_path, gui=False, timeout=300) -> CompletedProcess."""
    primed = subprocess.run(
        ["freecadcmd", "-c", PRIME_USER_CONFIG],
        capture_output=True,
        text=True,
        env=freecad_env(tmp_path_factory.mktemp("prime")),
        timeout=120,
    )
    assert primed.returncode == 0, primed.stdout + primed.stderr

    def run(script: str, tmp_path, gui: bool = False, timeout: int = 300):
        return run_script(script, tmp_path, gui, timeout)

    return run


@pytest.fixture(scope="session")
def assert_passed():
    """assert_passed(out, name): the script's check `name` passed; else show FreeCAD's output."""

    def check(out: subprocess.CompletedProcess, name: str) -> None:
        assert f"CHECK PASSED {name}" in out.stdout, (out.stdout + out.stderr)[-6000:]

    return check


@pytest.fixture(scope="session")
def assert_all_ran():
    """assert_all_ran(out, checks): the script exited 0 and ran exactly `checks`, in order."""

    def check(out: subprocess.CompletedProcess, checks: list) -> None:
        assert out.returncode == 0, (out.stdout + out.stderr)[-6000:]
        ran = [line.split()[-1] for line in out.stdout.splitlines() if line.startswith("CHECK ")]
        assert ran == checks

    return check
