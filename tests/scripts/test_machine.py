# SPDX-License-Identifier: LGPL-2.1-or-later
"""scripts/machine.py: every benchmark's first line says how fast the host runs now, so
that figures from a slower moment are not taken for slower code."""
import importlib.util
import math
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "machine.py"


def _machine():
    spec = importlib.util.spec_from_file_location("machine", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_host_speed_is_two_cpu_times_of_fixed_work():
    loop, sort = _machine().host_speed(repeats=3)
    assert all(math.isfinite(x) and 0 < x < 10_000 for x in (loop, sort))


def test_the_machine_line_says_the_host_speed_beside_the_versions():
    line = _machine().machine_line()
    assert "host speed: Python loop " in line and " ms, numpy sort " in line
    assert "torch " in line and "cores" in line
