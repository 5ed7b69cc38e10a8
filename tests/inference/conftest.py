# SPDX-License-Identifier: LGPL-2.1-or-later
"""Fixtures for the inference tests."""

import pytest

from Sketch2CADWorkbench.render.maps import MapRenderer


@pytest.fixture(scope="module")
def renderer():
    """A map renderer, reused by a module's tests."""
    return MapRenderer()
