# SPDX-License-Identifier: LGPL-2.1-or-later
"""Stroke rasterisation: the polyline's pixels, its value, 8-connected, later wins."""

import numpy as np
import pytest

from Sketch2CADWorkbench.render.strokes import rasterize, rasterize_index


def test_a_horizontal_segment_fills_the_pixels_between_its_ends():
    img = rasterize([np.array([[2.5, 3.5], [9.5, 3.5]])], 12, 8)
    expected = np.zeros((8, 12), np.float32)
    expected[3, 2:10] = 1.0  # pixel i has its centre at i + 0.5
    assert img.dtype == np.float32 and np.array_equal(img, expected)


def test_later_strokes_overwrite_earlier_ones_with_their_values():
    lines = [np.array([[2.5, 3.5], [9.5, 3.5]]), np.array([[5.5, 0.5], [5.5, 7.5]])]
    img = rasterize(lines, 12, 8, values=[1.0, 2.0])
    assert np.all(img[3, 2:10] == np.where(np.arange(2, 10) == 5, 2.0, 1.0))
    assert np.all(img[:, 5] == 2.0)
    assert (img > 0).sum() == 8 + 8 - 1
    index = rasterize_index(lines, 12, 8)
    assert np.array_equal(index >= 0, img > 0) and np.all(index[:, 5] == 1)
    assert index[3, 2] == 0 and index[0, 0] == -1


def test_a_diagonal_is_eight_connected_one_pixel_per_column():
    img = rasterize([np.array([[0.5, 0.5], [20.5, 10.5]])], 24, 12)
    cols = np.flatnonzero(img.any(axis=0))
    assert cols.tolist() == list(range(21))
    assert np.all(img.sum(axis=0)[cols] == 1.0)
    rows = [np.flatnonzero(img[:, c])[0] for c in cols]
    assert rows[0] == 0 and rows[-1] == 10 and np.all(np.diff(rows) >= 0)
    assert np.all(np.diff(rows) <= 1)


def test_a_lone_point_marks_its_pixel_and_thickness_widens_lines():
    img = rasterize([np.array([[4.2, 6.9]])], 10, 10)
    assert img[6, 4] == 1.0 and img.sum() == 1.0
    thin = rasterize([np.array([[1.5, 5.5], [8.5, 5.5]])], 10, 10)
    thick = rasterize([np.array([[1.5, 5.5], [8.5, 5.5]])], 10, 10, thickness=3)
    assert thick.sum() > 2 * thin.sum()


def test_values_must_match_the_polylines():
    with pytest.raises(ValueError):
        rasterize([np.zeros((2, 2))], 4, 4, values=[1.0, 2.0])
