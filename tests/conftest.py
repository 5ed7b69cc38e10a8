# SPDX-License-Identifier: LGPL-2.1-or-later
"""Shared test settings."""
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture
def examples_dir() -> Path:
    return ROOT / "examples" / "protocols"
