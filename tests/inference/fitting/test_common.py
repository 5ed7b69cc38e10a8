# SPDX-License-Identifier: LGPL-2.1-or-later
"""Stroke helpers every fit uses: which strokes are loops, which curve a stroke draws."""
import numpy as np

from Sketch2CADWorkbench.inference.fitting.common import match_ends, open_ends


def loop(centre, radius, start_angle, gap=0.2):
    t = np.linspace(start_angle, start_angle + 2 * np.pi - gap, 60)
    return np.asarray(centre) + radius * np.stack([np.cos(t), np.sin(t)], axis=1)


def test_a_circle_drawn_once_around_has_no_ends_and_a_line_keeps_both():
    line = np.array([[0.0, 0.0], [10.0, 1.0], [20.0, 0.0]])
    # the level-3 hand leaves a loop's ends apart by half its extent
    ends = open_ends([loop((50, 50), 10, 1.0), loop((80, 20), 10, 0.0, gap=1.0), line])
    assert ends.shape == (1, 2, 2)
    assert np.allclose(ends[0], [[0.0, 0.0], [20.0, 0.0]])


def test_each_stroke_is_matched_to_the_curve_whose_ends_it_draws_either_way():
    curves = np.array([[[0, 0], [10, 0]], [[0, 5], [0, 20]], [[30, 0], [30, 30]]], float)
    # drawn in another order, the second one backwards, each end a little off
    strokes = np.array([[[30, 1], [29, 31]], [[1, 21], [0, 6]], [[1, 0], [11, 1]]], float)
    rows, cols, swapped = match_ends(curves, strokes)
    got = {int(r): (int(c), bool(s)) for r, c, s in zip(rows, cols, swapped)}
    assert got == {0: (2, False), 1: (1, True), 2: (0, False)}


def test_strokes_beyond_the_curves_are_left_unmatched():
    curves = np.array([[[0, 0], [10, 0]]], float)
    strokes = np.array([[[50, 50], [60, 60]], [[0, 1], [10, 1]]], float)
    rows, cols, _ = match_ends(curves, strokes)
    assert list(rows) == [1] and list(cols) == [0]
    assert len(match_ends(curves, np.zeros((0, 2, 2)))[0]) == 0
