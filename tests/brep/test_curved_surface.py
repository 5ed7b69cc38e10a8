# SPDX-License-Identifier: LGPL-2.1-or-later
"""A cylinder's or cone's side in closed form (brep/faces.CurvedSurface): its normals are
OCCT's, and lines cross it where OCCT's face lies."""

import math

import cadquery as cq
import numpy as np
import pytest

from Sketch2CADWorkbench.brep.faces import CurvedSurface, is_curved


def rod():
    return cq.Solid.makeCylinder(10.0, 60.0, cq.Vector(0, 0, 0), cq.Vector(0, 0, 1))


def cone():
    return cq.Solid.makeCone(12.0, 6.0, 40.0, cq.Vector(5, -3, 2), cq.Vector(1, 2, 2))


def tube():
    inner = cq.Solid.makeCylinder(6.0, 60.0, cq.Vector(0, 0, 0), cq.Vector(0, 0, 1))
    return rod().cut(inner).Solids()[0]


def curved_faces(solid):
    return [f for f in solid.Faces() if is_curved(f)]


def face_points(face, n=7):
    """Points of the face on an n x n grid of its parameters."""
    u0, u1, v0, v1 = face.uvBounds()
    adaptor = face._geomAdaptor()
    return np.array(
        [
            adaptor.Value(u, v).Coord()
            for u in np.linspace(u0, u1, n)
            for v in np.linspace(v0, v1, n)
        ]
    )


@pytest.mark.parametrize("solid", [rod, cone, tube])  # the tube has a bore's concave wall
def test_normals_are_occts_at_points_of_the_face(solid):
    for face in curved_faces(solid()):
        points = face_points(face)
        occt = np.array([face.normalAt(cq.Vector(*p)).toTuple() for p in points])
        assert np.abs(CurvedSurface.of(face).normals(points) - occt).max() < 1e-9


@pytest.mark.parametrize("solid", [rod, cone])
def test_lines_along_the_normal_cross_the_surface_on_the_face(solid):
    (face,) = curved_faces(solid())
    surface = CurvedSurface.of(face)
    on = face_points(face)[7:-7]  # off the rims, where a line may graze an end cap
    normals = surface.normals(on)
    rng = np.random.default_rng(0)
    lift = rng.uniform(-3.0, 3.0, len(on))
    t = surface.crossings(on + lift[:, None] * normals[0], normals[0], 100.0)
    hits = on + lift[:, None] * normals[0] + t[:, None] * normals[0]
    assert not np.isnan(t).any()
    assert max(face.distance(cq.Vertex.makeVertex(*p)) for p in hits) < 1e-9
    assert np.abs(surface.level(hits)).max() < 1e-9


def test_a_line_through_a_rod_enters_then_leaves_it_at_the_chords_ends():
    surface = CurvedSurface.of(curved_faces(rod())[0])
    a = 6.0  # the line y = a, z = 30 along -x, from x = 20
    k, t, entering = surface.roots(
        np.array([[20.0, a, 30.0]]), np.array([-1.0, 0, 0]), -100.0, 100.0
    )
    half = math.sqrt(10.0**2 - a**2)
    assert k.tolist() == [0, 0] and entering.tolist() == [True, False]
    assert np.allclose(t, [20.0 - half, 20.0 + half], rtol=0, atol=1e-12)


def test_lines_that_miss_or_only_touch_the_surface_do_not_cross_it():
    surface = CurvedSurface.of(curved_faces(rod())[0])
    points = np.array(
        [
            [20.0, 12.0, 30.0],  # passes beside the rod
            [20.0, 10.0, 30.0],  # touches it along y = 10
            [5.0, 0.0, 30.0],
        ]
    )  # runs along the axis, inside
    for p, direction in zip(points, ([-1.0, 0, 0], [-1.0, 0, 0], [0, 0, 1.0]), strict=False):
        assert np.isnan(surface.crossings(p[None], np.array(direction), 100.0)).all()
    # only the nearer crossing within the span counts
    (t,) = surface.crossings(np.array([[20.0, 0.0, 30.0]]), np.array([-1.0, 0, 0]), 15.0)
    assert t == pytest.approx(10.0, abs=1e-12)


def test_a_line_parallel_to_a_cones_generatrix_crosses_it_once():
    surface = CurvedSurface.of(
        curved_faces(cq.Solid.makeCone(10.0, 0.0, 20.0, cq.Vector(0, 0, 0), cq.Vector(0, 0, 1)))[0]
    )
    generatrix = np.array([-10.0, 0.0, 20.0]) / math.hypot(10.0, 20.0)
    # x = 9 - z / 2, inside the cone along the generatrix x = 10 - z / 2: it leaves the
    # cone through the opposite generatrix x = z / 2 - 10, at z = 19 (beyond that, it
    # would meet the nappe past the apex)
    k, t, entering = surface.roots(np.array([[9.0, 0.0, 0.0]]), generatrix, -100.0, 100.0)
    assert k.tolist() == [0] and entering.tolist() == [False]
    assert np.allclose(
        np.array([9.0, 0.0, 0.0]) + t[0] * generatrix, [-0.5, 0.0, 19.0], rtol=0, atol=1e-9
    )
