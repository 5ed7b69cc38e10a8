# SPDX-License-Identifier: LGPL-2.1-or-later
"""What a benchmark ran on, printed beside its figures so that they compare across
stops: the CPU model, cores, load, and the versions of the libraries that do the work.

Stop 24 found the CPU per data sample doubled with the same code and could not say
whether the host or the reinstalled libraries were the cause (docs/NOTES.md).
"""
from __future__ import annotations

import importlib.metadata
import os
import platform
from pathlib import Path

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


def machine_line() -> str:
    """One line: CPU, cores, load average, Python and library versions."""
    libs = ", ".join(f"{k} {v}" for k, v in library_versions().items())
    return (f"machine: {cpu_model()}, {os.cpu_count()} cores, load {os.getloadavg()[0]:.2f}; "
            f"Python {platform.python_version()}, {libs}")
