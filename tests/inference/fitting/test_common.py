# SPDX-License-Identifier: LGPL-2.1-or-later
"""Stroke helpers every fit uses: which strokes are loops, which curve a stroke draws."""

import numpy as np
import pytest

from Sketch2CADWorkbench.brep.geometry import bezier
from Sketch2CADWorkbench.inference.fitting.common import (
    box_least_squares,
    fit_bezier,
    match_ends,
    open_ends,
)


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
    got = {int(r): (int(c), bool(s)) for r, c, s in zip(rows, cols, swapped, strict=False)}
    assert got == {0: (2, False), 1: (1, True), 2: (0, False)}


def test_strokes_beyond_the_curves_are_left_unmatched():
    curves = np.array([[[0, 0], [10, 0]]], float)
    strokes = np.array([[[50, 50], [60, 60]], [[0, 1], [10, 1]]], float)
    rows, cols, _ = match_ends(curves, strokes)
    assert list(rows) == [1] and list(cols) == [0]
    assert len(match_ends(curves, np.zeros((0, 2, 2)))[0]) == 0


def test_a_curve_fitted_within_a_corner_keeps_its_polygon_there_and_misses_nothing_inside():
    corner, start, end = np.array([0.0, 0.0]), np.array([10.0, 0.0]), np.array([0.0, 8.0])
    t = np.linspace(0, 1, 50)
    # a fillet inside the corner's parallelogram: the bounded fit finds it as the free one
    fillet = np.array([start, [4.0, 0.0], [0.0, 3.0], end])
    bounded = fit_bezier(bezier(fillet, t), start, end, corner=corner, span=0.9)
    dense = bezier(bounded, np.linspace(0, 1, 400))
    gap = np.linalg.norm(bezier(fillet, t)[:, None] - dense[None], axis=-1).min(1)
    assert gap.max() < 0.1  # mm, on a 10 x 8 mm corner
    # a curve swinging out past both ends: its inner control points stay in the corner
    swing = np.array([start, [18.0, 12.0], [9.0, 16.0], end])
    ctrl = fit_bezier(bezier(swing, t), start, end, corner=corner, span=0.9)
    st = np.linalg.solve(np.stack([start - corner, end - corner], 1), (ctrl[1:3] - corner).T)
    assert st.min() >= -1e-9 and st.max() <= 0.9 + 1e-9
    assert (
        np.abs(
            st
            - np.clip(np.linalg.solve(np.stack([start, end], 1), (swing[1:3] - corner).T), 0, 0.9)
        ).max()
        < 0.3
    )


def test_a_box_bounded_least_squares_is_the_least_residual_within_its_bounds():
    rng = np.random.default_rng(3)
    for _ in range(50):
        a = rng.normal(size=(40, 4))
        b = rng.normal(size=40) * rng.uniform(0.1, 4.0)
        x = box_least_squares(a, b, 0.0, 1.2)
        assert np.all((x >= 0.0) & (x <= 1.2))
        best = np.sum((a @ x - b) ** 2)
        # no point of the box nearby, nor any corner of it, leaves a smaller residual
        for y in np.clip(x + rng.normal(scale=0.05, size=(200, 4)), 0.0, 1.2):
            assert np.sum((a @ y - b) ** 2) >= best - 1e-9
    inside = np.array([0.3, 0.5, 0.7, 0.9])  # an unbounded solution inside is kept
    a = rng.normal(size=(40, 4))
    assert box_least_squares(a, a @ inside, 0.0, 1.2) == pytest.approx(inside)
