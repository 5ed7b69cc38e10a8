# SPDX-License-Identifier: LGPL-2.1-or-later
"""Shared test settings."""

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
# a tiny model config and tiny on-disk data sets, for the network and training tests
pytest_plugins = ["network_fixtures"]


@pytest.fixture
def examples_dir() -> Path:
    return ROOT / "examples" / "protocols"
