# SPDX-License-Identifier: LGPL-2.1-or-later
"""The lines a designer who leaves hidden lines out draws: what the view sees of the
model after the operation, line by line (sketch/visible.py)."""

import numpy as np
import pytest

from Sketch2CADWorkbench.brep.operators import apply_operation, make_box
from Sketch2CADWorkbench.brep.protocol import AddSubPrism, Box, FaceRef, Mode
from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.sketch.curves import operation_curves
from Sketch2CADWorkbench.sketch.labels import END, PROFILE, START
from Sketch2CADWorkbench.sketch.visible import visible_curves

TOP = FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0))
SQUARE = ((-5.0, -5.0, 10.0), (5.0, -5.0, 10.0), (5.0, 5.0, 10.0), (-5.0, 5.0, 10.0))


@pytest.fixture(scope="module")
def view():
    d = np.array([0.3, 0.8, -1.0])  # from above, in front of the top face's -y side
    return OrthoCamera((0.0, 0.0, 5.0), tuple(d / np.linalg.norm(d)), (0, 0, 1), 45.0, 512, 512)


def seen(op, view, renderer):
    box = make_box(Box((40, 30, 20)))
    curves = operation_curves(box, op, view.direction)
    return curves, visible_curves(curves, view, renderer.render(apply_operation(box, op), view))


def length(curves, view, label):
    return sum(
        float(np.linalg.norm(np.diff(view.project(c.points)[0], axis=0), axis=1).sum())
        for c in curves
        if c.label == label
    )


def test_a_boss_shows_its_top_outline_whole_and_hides_part_of_its_base(view, renderer):
    curves, shown = seen(AddSubPrism(TOP, SQUARE, 6.0, Mode.ADD), view, renderer)
    assert length(shown, view, END) == pytest.approx(length(curves, view, END), rel=1e-6)
    assert 0.3 < length(shown, view, START) / length(curves, view, START) < 0.8
    assert length(shown, view, PROFILE) < length(curves, view, PROFILE)
    assert all(any(c is k for k in curves) for c in shown if c.label == END)  # whole lines kept


def test_a_hole_shows_its_rim_whole_and_hides_the_near_part_of_its_floor(view, renderer):
    curves, shown = seen(AddSubPrism(TOP, SQUARE, 6.0, Mode.SUBTRACT), view, renderer)
    assert length(shown, view, END) == pytest.approx(length(curves, view, END), rel=1e-6)
    assert 0.2 < length(shown, view, START) / length(curves, view, START) < 0.8
    floor = [c for c in shown if c.label == START]
    # the floor's near edge (y = -5) lies behind the hole's near wall
    assert all(np.all(c.points[:, 1] > -5.0 + 1e-6) for c in floor), floor
