# SPDX-License-Identifier: LGPL-2.1-or-later
"""Shared test settings."""

import importlib.util
import os
import stat
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
# a tiny model config and tiny on-disk data sets, for the network and training tests
pytest_plugins = ["network_fixtures"]


@pytest.fixture
def examples_dir() -> Path:
    return ROOT / "examples" / "protocols"


@pytest.fixture
def load_file():
    """A file of the repository that is not a module of a package (scripts/NAME.py,
    benchmarks/NAME.py), loaded as a fresh module: load_file("scripts/make_sessions")."""

    def load(name: str):
        spec = importlib.util.spec_from_file_location(Path(name).name, ROOT / f"{name}.py")
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        return module

    return load


@pytest.fixture
def memory_device():
    """Makes a character device of the memory driver: memory_device(path, minor) (minor 3:
    like /dev/null, 5: /dev/zero, 7: /dev/full), in the test's folder so that the machine's
    own device files are never written. `make test` runs as root, as its setup needs;
    elsewhere the test fails saying so."""

    def make(path: Path, minor: int) -> Path:
        try:
            os.mknod(path, 0o666 | stat.S_IFCHR, os.makedev(1, minor))
        except PermissionError:
            pytest.fail("making a device node needs root: run the tests as `make test` does")
        return path

    return make
