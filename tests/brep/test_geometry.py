# SPDX-License-Identifier: LGPL-2.1-or-later
"""Polyline helpers that every stroke and curve sample goes through."""

import numpy as np
import pytest

from Sketch2CADWorkbench.brep.geometry import arc_lengths, polyline_length, resample_every
from Sketch2CADWorkbench.inference.fitting.common import resample


def _walk(seed: int, points: int, dims: int) -> np.ndarray:
    return np.cumsum(np.random.default_rng(seed).normal(size=(points, dims)) * 3.0, axis=0)


@pytest.mark.parametrize("dims", [2, 3])
def test_arc_lengths_are_the_running_sum_of_euclidean_segment_lengths(dims):
    p = _walk(1, 50, dims)
    expected = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])
    assert np.array_equal(arc_lengths(p), expected)  # bit for bit: data generation's bytes


def test_a_polylines_length_is_its_last_arc_length_and_a_point_has_none():
    assert polyline_length([[0, 0], [3, 4], [3, 10]]) == 11.0
    p = _walk(3, 30, 3)
    assert polyline_length(p) == arc_lengths(p)[-1]
    assert polyline_length([[1.0, 2.0]]) == 0.0


@pytest.mark.parametrize("step", [0.5, 1.0, 3.0])
def test_a_polyline_resampled_every_step_keeps_its_ends_and_even_spacing(step):
    p = _walk(2, 40, 2)
    q = resample_every(p, step)
    assert np.array_equal(q[0], p[0]) and np.allclose(q[-1], p[-1])
    spacing = arc_lengths(p)[-1] / (len(q) - 1)
    assert spacing <= step and spacing > step * (len(q) - 2) / (len(q) - 1)
    # points lie on the polyline: each is within float error of some segment
    a, b = p[:-1], p[1:]
    t = np.clip(np.einsum("qsk,sk->qs", q[:, None] - a, b - a) / ((b - a) ** 2).sum(1), 0, 1)
    gap = np.linalg.norm(a + t[..., None] * (b - a) - q[:, None], axis=2).min(1)
    assert gap.max() < 1e-9


def test_given_lengths_resample_as_computed_ones():
    p = _walk(3, 30, 3)
    assert np.array_equal(resample_every(p, 1.0, arc_lengths(p)), resample_every(p, 1.0))


def test_a_stroke_of_no_length_resamples_to_its_one_point():
    assert np.array_equal(resample(np.array([[4.0, 5.0], [4.0, 5.0]])), [[4.0, 5.0]])
    assert np.array_equal(resample(np.array([[4.0, 5.0]])), [[4.0, 5.0]])
