# SPDX-License-Identifier: LGPL-2.1-or-later
"""The camera's checks on its vectors: what a session or the FreeCAD view hands it."""

import numpy as np
import pytest

from Sketch2CADWorkbench.render.camera import OrthoCamera


def test_a_zero_up_is_refused_as_zero_not_as_parallel():
    with pytest.raises(ValueError, match="up must be a non-zero vector"):
        OrthoCamera((0, 0, 0), (1, 1, 0), (0, 0, 0), 10.0)


def test_an_up_along_the_direction_is_refused():
    with pytest.raises(ValueError, match="parallel to direction"):
        OrthoCamera((0, 0, 0), (1, 1, 0), (2, 2, 0), 10.0)


@pytest.mark.parametrize("scale", [1e200, 1e-6])
def test_a_direction_of_any_finite_length_is_the_same_view(scale):
    # a huge direction's squared length overflows: it must not become "not in view"
    unit = OrthoCamera((0, 0, 0), (np.sqrt(0.5), np.sqrt(0.5), 0), (0, 0, 1), 10.0, 80, 60)
    big = OrthoCamera((0, 0, 0), (scale, scale, 0), (0, 0, scale), 10.0, 80, 60)
    points = [(1.0, 2.0, 3.0), (-4.0, 0.5, 2.0)]
    for got, want in zip(big.project(points), unit.project(points), strict=True):
        np.testing.assert_allclose(got, want, atol=1e-9)


def test_the_basis_is_made_once_and_cannot_be_changed_by_a_caller():
    cam = OrthoCamera((1.0, 2.0, 3.0), (0.6, 0.9, -1.2), (0, 0, 1), 45.0)
    r, u, f = cam.basis()
    assert cam.basis()[0] is r
    np.testing.assert_allclose(np.stack([r, u, f]) @ np.stack([r, u, f]).T, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(np.cross(f, u), r)
    with pytest.raises(ValueError):
        u *= 2.0
