# SPDX-License-Identifier: LGPL-2.1-or-later
"""Corners a bevel can round and the creases leaving them."""

import cadquery as cq
import numpy as np

from Sketch2CADWorkbench.brep.corners import bevel_corners, crease_end, creases


def _l_shape() -> cq.Solid:
    """A 40 x 40 x 10 plate minus its +x+y quarter: the top face has one reflex corner."""
    plate = cq.Solid.makeBox(40, 40, 10)
    return plate.cut(cq.Solid.makeBox(20, 20, 10, cq.Vector(20, 20, 0))).Solids()[0]


def test_bevel_corners_are_the_convex_corners_with_a_perpendicular_crease():
    solid = _l_shape()
    top = next(f for f in solid.Faces() if f.Center().z > 9.9)
    corners = bevel_corners(solid, top, np.array([0.0, 0.0, 1.0]), 1e-4)
    got = sorted(tuple(np.round(c.c[:2]).astype(int)) for c in corners)
    assert got == [(0, 0), (0, 40), (20, 40), (40, 0), (40, 20)]  # not the reflex (20, 20)
    for c in corners:
        assert np.allclose(c.opposite, c.c - [0, 0, 10])


def test_creases_run_into_the_solid_along_the_face_normal():
    solid = _l_shape()
    up = np.array([0.0, 0.0, 1.0])
    found = creases(solid, up)
    assert len(found) == 6  # the six vertical edges, each once, from top to bottom
    for s, t in found:
        assert np.allclose(t - s, [0, 0, -10])
    assert np.allclose(crease_end(solid, np.array([20.0, 20.0, 10.0]), up, 1e-4), [20, 20, 0])
    assert crease_end(solid, np.array([10.0, 10.0, 10.0]), up, 1e-4) is None
