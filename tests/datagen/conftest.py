# SPDX-License-Identifier: LGPL-2.1-or-later
"""Shared fixtures for the data generation tests: one renderer, one sample per operator."""

import numpy as np
import pytest

from datagen.generate import Context, sample_on
from datagen.sequences import sample_sequence
from Sketch2CADWorkbench.brep.protocol import OperatorType
from Sketch2CADWorkbench.render.maps import MapRenderer


@pytest.fixture(scope="session")
def renderer():
    return MapRenderer()


@pytest.fixture(scope="session")
def per_operator(renderer):
    """Two samples of each operator at noise level 1: one on a plain box, one on a
    context of two operations."""
    out = {}
    for k, kind in enumerate(OperatorType):
        out[kind] = [
            sample_on(
                Context(sample_sequence(np.random.default_rng([k, n]), n)),
                np.random.default_rng([k, n, 1]),
                1,
                renderer,
                kind=kind,
            )
            for n in (0, 2)
        ]
    return out
