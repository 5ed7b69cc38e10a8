# SPDX-License-Identifier: LGPL-2.1-or-later
"""Shared test settings."""

import importlib.util
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
