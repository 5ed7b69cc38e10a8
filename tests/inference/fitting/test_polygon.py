# SPDX-License-Identifier: LGPL-2.1-or-later
"""An outline's corners from its sides drawn one stroke each (fitting/polygon.py)."""

import numpy as np
import pytest

from Sketch2CADWorkbench.inference.fitting.common import FitError
from Sketch2CADWorkbench.inference.fitting.polygon import side_corners


def sides(corners, gap=0.0):
    """One stroke per side of the polygon, each stopping `gap` pixels short of its end."""
    corners = np.asarray(corners, float)
    out = []
    for a, b in zip(corners, np.roll(corners, -1, axis=0), strict=True):
        u = (b - a) / np.linalg.norm(b - a)
        out.append(np.linspace(a, b - gap * u, 10))
    return out


SQUARE = [(0, 0), (40, 0), (40, 40), (0, 40)]


def test_the_corners_of_a_closed_outline_are_where_its_sides_meet():
    got = side_corners(sides(SQUARE, gap=4.0), reach=10.0)
    assert len(got) == 4
    for c in SQUARE:
        assert np.min(np.linalg.norm(got - c, axis=1)) < 2.5


def test_with_a_reach_sides_that_stop_far_apart_are_no_outline():
    strokes = sides(SQUARE, gap=15.0)
    assert len(side_corners(strokes)) == 4  # without a reach, any ends pair up
    with pytest.raises(FitError, match="do not meet end to end"):
        side_corners(strokes, reach=10.0)


def test_with_a_reach_two_loops_are_no_one_outline():
    two = sides([(0, 0), (20, 0), (10, 15)]) + sides([(60, 0), (80, 0), (70, 15)])
    assert len(side_corners(two)) == 6
    with pytest.raises(FitError, match="do not meet end to end"):
        side_corners(two, reach=10.0)
