# SPDX-License-Identifier: LGPL-2.1-or-later
"""benchmarks/machine.py: every benchmark's first line says how fast the host runs now, so
that figures from a slower moment are not taken for slower code."""

import math


def test_the_host_speed_is_two_cpu_times_of_fixed_work(load_file):
    loop, sort = load_file("benchmarks/machine").host_speed(repeats=3)
    assert all(math.isfinite(x) and 0 < x < 10_000 for x in (loop, sort))


def test_the_machine_line_says_the_host_speed_beside_the_versions(load_file):
    line = load_file("benchmarks/machine").machine_line()
    assert "host speed: Python loop " in line and " ms, numpy sort " in line
    assert "torch " in line and "cores" in line
