# SPDX-License-Identifier: LGPL-2.1-or-later
"""Tessellation: every face, its index, outward normals, and curves within tolerance."""

import cadquery as cq
import numpy as np
import pytest

from Sketch2CADWorkbench.brep.faces import indexed_faces, model_scale
from Sketch2CADWorkbench.render.mesh import (
    ANGULAR_TOLERANCE,
    REL_TOLERANCE,
    tessellate,
    view_tolerance,
)


@pytest.fixture(scope="module")
def holed_box():
    """A box with a round hole through it and a cone on top: planes, cylinder, cone."""
    body = cq.Solid.makeBox(40, 30, 20, cq.Vector(-20, -15, 0))
    body = body.cut(cq.Solid.makeCylinder(6, 40, cq.Vector(-8, 0, -10)))
    return body.fuse(cq.Solid.makeCone(6, 2, 10, cq.Vector(10, 0, 20))).clean()


def test_the_indexed_face_map_lists_the_faces_in_the_order_of_faces(holed_box):
    faces = holed_box.Faces()
    mapped = indexed_faces(holed_box)
    assert mapped.Extent() == len(faces)
    assert all(mapped.FindKey(i + 1).IsSame(f.wrapped) for i, f in enumerate(faces))


def test_every_face_is_triangulated_with_its_index_and_outward_normals(holed_box):
    mesh = tessellate(holed_box)
    faces = holed_box.Faces()
    assert set(mesh.face_index.tolist()) == set(range(len(faces)))
    assert mesh.vertices.dtype == np.float64 and mesh.triangles.shape[1] == 3
    assert mesh.normals.shape == mesh.triangles.shape
    assert mesh.vertex_normals.shape == mesh.vertices.shape
    centroids = mesh.vertices[mesh.triangles].mean(axis=1)
    for k in range(0, len(centroids), 7):
        face = faces[mesh.face_index[k]]
        on_face = face.Center() if face.geomType() == "PLANE" else cq.Vector(*centroids[k])
        true_normal = np.array(face.normalAt(on_face).toTuple())
        assert mesh.normals[k] @ true_normal > 0.98
        assert face.distance(cq.Vertex.makeVertex(*centroids[k])) < 0.1
    assert np.allclose(np.linalg.norm(mesh.vertex_normals, axis=1), 1.0)
    assert np.allclose(np.linalg.norm(mesh.normals, axis=1), 1.0)


def test_a_cylinder_mesh_stays_within_the_chordal_and_angular_tolerances():
    radius = 10.0
    cyl = cq.Solid.makeCylinder(radius, 20.0)
    side = next(i for i, f in enumerate(cyl.Faces()) if f.geomType() == "CYLINDER")
    tol = 0.01
    mesh = tessellate(cyl, tol)
    tris = mesh.triangles[mesh.face_index == side]
    v = mesh.vertices[np.unique(tris)]
    assert np.allclose(np.hypot(v[:, 0], v[:, 1]), radius, atol=1e-5)  # nodes on the surface
    # A chord's midpoint lies inside the circle by the sagitta, which must be <= tol.
    mid = mesh.vertices[tris].mean(axis=1)
    assert np.hypot(mid[:, 0], mid[:, 1]).min() >= radius - tol
    # Smooth vertex normals are the radial directions.
    n = mesh.vertex_normals[np.unique(tris)]
    assert np.allclose(n[:, :2], v[:, :2] / radius, atol=1e-4)
    assert np.allclose(n[:, 2], 0.0, atol=1e-4)


def test_the_default_tolerance_is_relative_to_the_model_size():
    small = cq.Solid.makeCylinder(1.0, 2.0)
    big = small.scale(100.0)
    n_small, n_big = len(tessellate(small).triangles), len(tessellate(big).triangles)
    assert n_small == pytest.approx(n_big, rel=0.2)
    # The default segments meet the angular tolerance on any scale.
    ring = tessellate(small)
    angles = np.arctan2(ring.vertices[:, 1], ring.vertices[:, 0])
    assert len(np.unique(np.round(angles, 6))) >= 2 * np.pi / ANGULAR_TOLERANCE


def test_view_tolerance_is_half_a_pixel_within_model_relative_bounds(holed_box):
    size = model_scale(holed_box)
    assert view_tolerance(size, 1e-3 * size) == pytest.approx(0.5e-3 * size)
    assert view_tolerance(size, size) == pytest.approx(REL_TOLERANCE * size)
    assert view_tolerance(size, 1e-9 * size) < view_tolerance(size, 1e-3 * size)


def test_tessellating_a_shape_without_faces_is_an_error():
    with pytest.raises(ValueError):
        tessellate(cq.Edge.makeLine(cq.Vector(0, 0, 0), cq.Vector(1, 0, 0)))
    with pytest.raises(ValueError):
        tessellate(cq.Solid.makeBox(1, 1, 1), tolerance=0.0)
