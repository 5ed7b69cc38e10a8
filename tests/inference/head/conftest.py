# SPDX-License-Identifier: LGPL-2.1-or-later
"""Fixtures for the structured head's tests."""

import pytest
import torch

from Sketch2CADWorkbench.inference.models import Sketch2CADNet


@pytest.fixture
def net(tiny_config):
    torch.manual_seed(0)
    return Sketch2CADNet(tiny_config).eval()
