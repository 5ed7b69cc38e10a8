# SPDX-License-Identifier: LGPL-2.1-or-later
"""Which points lie on a face (as OCCT's classifier tells them), and faces read without wrapping
each one: by index, their kinds, planar normals."""

import cadquery as cq
import numpy as np
import pytest
from OCP.BRepClass import BRepClass_FaceClassifier
from OCP.gp import gp_Pnt
from OCP.TopAbs import TopAbs_IN, TopAbs_ON

from Sketch2CADWorkbench.brep.faces import (
    FaceFrame,
    face_at,
    face_kinds,
    face_ref_at,
    plane_normals,
    points_on_face,
    resolve_face,
)

BOX = cq.Solid.makeBox(40, 30, 20, cq.Vector(-20, -15, -10))
SOLIDS = {
    "box": BOX,
    "through hole": BOX.cut(cq.Solid.makeBox(10, 8, 40, cq.Vector(-5, -4, -20))),
    "notch": BOX.cut(cq.Solid.makeBox(15, 15, 8, cq.Vector(5, 0, 2))),
    "round hole": BOX.cut(cq.Solid.makeCylinder(5, 40, cq.Vector(12, 8, -20))),
    "turned": BOX.cut(cq.Solid.makeBox(10, 8, 40, cq.Vector(-5, -4, -20))).rotate(
        cq.Vector(0, 0, 0), cq.Vector(1, 2, 3), 33
    ),
}


def occt(face, points, tol, boundary):
    states = (TopAbs_IN, TopAbs_ON) if boundary else (TopAbs_IN,)
    classifier = BRepClass_FaceClassifier()
    out = []
    for p in points:
        classifier.Perform(face.wrapped, gp_Pnt(*map(float, p)), tol)
        out.append(classifier.State() in states)
    return np.array(out)


@pytest.mark.parametrize("name", SOLIDS)
def test_points_on_a_planar_face_are_told_as_occts_classifier_tells_them(name):
    rng = np.random.default_rng(len(name))
    for face in SOLIDS[name].Faces():
        if face.geomType() != "PLANE":
            continue
        frame = FaceFrame.of(face)
        corners = frame.to_2d(np.array([v.toTuple() for v in face.Vertices()]))
        lo, hi = corners.min(axis=0) - 3, corners.max(axis=0) + 3
        at = corners[rng.integers(0, len(corners), 30)]
        grid = np.stack(
            np.meshgrid(np.linspace(lo[0] + 3, hi[0] - 3, 7), np.linspace(lo[1] + 3, hi[1] - 3, 7)),
            -1,
        ).reshape(-1, 2)
        # anywhere, at the corners and just beside them, and on a grid over the face's box
        # (whose outer rows run along its sides), a hair off the plane
        flat = np.concatenate(
            [rng.uniform(lo, hi, (40, 2)), at, at + rng.normal(0, 1e-3, at.shape), grid]
        )
        points = frame.to_3d(flat) + rng.normal(0, 1e-9, (len(flat), 3))
        for tol in (1e-7, 0.3):
            for boundary in (True, False):
                np.testing.assert_array_equal(
                    points_on_face(face, points, tol, boundary), occt(face, points, tol, boundary)
                )


@pytest.mark.parametrize("name", SOLIDS)
def test_face_at_is_the_face_of_faces_at_that_index(name):
    faces = SOLIDS[name].Faces()
    for i, face in enumerate(faces):
        got = face_at(SOLIDS[name], i)
        assert got.isSame(face) and got.wrapped.Orientation() == face.wrapped.Orientation()
    with pytest.raises(IndexError):
        face_at(SOLIDS[name], len(faces))


@pytest.mark.parametrize("name", SOLIDS)
def test_face_kinds_and_plane_normals_are_cadquerys_face_by_face(name):
    faces = SOLIDS[name].Faces()
    assert face_kinds(SOLIDS[name]) == [f.geomType() for f in faces]
    normals = plane_normals(SOLIDS[name])
    assert sorted(normals) == [i for i, f in enumerate(faces) if f.geomType() == "PLANE"]
    for i, n in normals.items():  # outward, reversed faces included
        np.testing.assert_allclose(n, faces[i].normalAt().toTuple(), atol=1e-12)


def test_a_step_placed_past_a_curved_faces_edge_stands_on_the_face_and_resolves():
    post = cq.Solid.makeCylinder(5.0, 10.0)  # its side from z = 0 to 10
    side = next(f for f in post.Faces() if f.geomType() == "CYLINDER")
    ref = face_ref_at(side, (6.0, 0.0, 15.0))  # beyond the top rim, on the surface's line
    assert ref.point == pytest.approx((5.0, 0.0, 10.0), abs=1e-6)
    assert ref.normal == pytest.approx((1.0, 0.0, 0.0), abs=1e-6)
    assert resolve_face(post, ref).face.isSame(side)
    # a point on the face is only moved onto its surface
    assert face_ref_at(side, (6.0, 0.0, 4.0)).point == pytest.approx((5.0, 0.0, 4.0))
