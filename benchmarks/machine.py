# SPDX-License-Identifier: LGPL-2.1-or-later
"""What a benchmark ran on, printed beside its figures so that they compare across
hosts and days: the CPU model, cores, load, the versions of the libraries that do the work, and
how fast the host runs two fixed workloads right now.

The same code has measured twice the CPU per data sample on another host, and 134 and
157 ms per interpret step minutes apart on one idle machine. The host's speed drifts:
compare figures only beside equal host speeds.
"""

from __future__ import annotations

import importlib.metadata
import os
import platform
import statistics
import time
from pathlib import Path

import numpy as np

LIBRARIES = ("cadquery", "cadquery-ocp", "vtk", "torch", "numpy", "opencv-contrib-python-headless")


def cpu_model() -> str:
    """The CPU's model name (Linux /proc/cpuinfo; the platform's name elsewhere)."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def library_versions() -> dict[str, str]:
    """Installed version of each of LIBRARIES ("absent" when not installed)."""
    versions = {}
    for name in LIBRARIES:
        try:
            versions[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            versions[name] = "absent"
    return versions


def host_speed(repeats: int = 5) -> tuple[float, float]:
    """CPU milliseconds (this thread; the median of `repeats`) of two fixed workloads: a
    pure-Python loop of 200,000 additions, and numpy sorting 200,000 floats (one thread,
    no BLAS), so that two figures taken on differently loaded or throttled hosts can be
    told apart from a change of the code."""
    values = np.random.default_rng(0).random(200_000)

    def cpu_ms(work) -> float:
        times = []
        for _ in range(repeats):
            start = time.thread_time()
            work()
            times.append(1e3 * (time.thread_time() - start))
        return statistics.median(times)

    return cpu_ms(lambda: sum(range(200_000))), cpu_ms(lambda: np.sort(values))


def machine_line() -> str:
    """One line: CPU, cores, load average, host speed, Python and library versions."""
    libs = ", ".join(f"{k} {v}" for k, v in library_versions().items())
    loop, sort = host_speed()
    return (
        f"machine: {cpu_model()}, {os.cpu_count()} cores, load {os.getloadavg()[0]:.2f}, "
        f"host speed: Python loop {loop:.2f} ms, numpy sort {sort:.2f} ms; "
        f"Python {platform.python_version()}, {libs}"
    )
