# SPDX-License-Identifier: LGPL-2.1-or-later
"""Reprojection error: the operation that was drawn explains its strokes best."""
import numpy as np
import pytest

from Sketch2CADWorkbench.brep.operators import make_box
from Sketch2CADWorkbench.brep.protocol import Box, FaceRef, Mode, Sweep
from Sketch2CADWorkbench.inference.fitting.verify import reprojection_error
from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.sketch.curves import operation_curves

TOP = FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0))


def sweep(r1: float, d: float) -> Sweep:
    return Sweep(TOP, (2.0, 0.0, 10.0), 5.0, r1, d, ((5.0, d / 3), (r1, 2 * d / 3)), Mode.ADD)


def test_the_drawn_sweep_explains_its_strokes_better_than_a_longer_wider_one():
    box = make_box(Box((40, 30, 20)))
    d = np.array([0.6, 0.9, -1.2])
    cam = OrthoCamera((0.0, 0.0, 5.0), tuple(d / np.linalg.norm(d)), (0, 0, 1), 45.0, 800, 600)
    drawn = sweep(4.0, 10.0)
    strokes = [cam.project(c.points)[0] for c in operation_curves(box, drawn, cam.direction)]
    exact = reprojection_error(box, drawn, cam, strokes)
    assert exact == pytest.approx(0.0, abs=1.0)
    assert reprojection_error(box, sweep(9.0, 16.0), cam, strokes) > exact + 5.0
