# SPDX-License-Identifier: LGPL-2.1-or-later
"""Fixtures for the fitting tests: a box and a view of it."""

import numpy as np
import pytest
from fit_sketches import SIZE

from Sketch2CADWorkbench.brep.operators import make_box
from Sketch2CADWorkbench.brep.protocol import Box
from Sketch2CADWorkbench.render.camera import OrthoCamera


@pytest.fixture
def box():
    return make_box(Box(SIZE))


@pytest.fixture
def camera():
    """A view from above, in front and to the left: it sees the top, front and left faces."""
    d = np.array([0.7, 1.0, -1.1])
    return OrthoCamera((0.0, 0.0, 12.0), tuple(d / np.linalg.norm(d)), (0.0, 0.0, 1.0), 32.0)
