# SPDX-License-Identifier: LGPL-2.1-or-later
"""Triangulating a B-rep solid for rendering, keeping which B-rep face each triangle is on."""
from __future__ import annotations

from dataclasses import dataclass

import cadquery as cq
import numpy as np
from OCP.BRep import BRep_Tool
from OCP.TopAbs import TopAbs_REVERSED
from OCP.TopLoc import TopLoc_Location

from ..brep.faces import model_scale


@dataclass(frozen=True)
class FaceMesh:
    """A triangle mesh of a solid (world mm).

    Vertices are not shared between B-rep faces, so per-vertex normals are smooth
    within a face and sharp across its edges.

    Attributes:
        vertices: (V, 3) float64 positions.
        triangles: (T, 3) int32 vertex indices, counter-clockwise seen from outside.
        face_index: (T,) int32 index of each triangle's face in solid.Faces().
        normals: (V, 3) float64 outward unit vertex normals.
    """

    vertices: np.ndarray
    triangles: np.ndarray
    face_index: np.ndarray
    normals: np.ndarray


def tessellate(solid: cq.Shape, tolerance: float | None = None,
               angular_tolerance: float = 0.2) -> FaceMesh:
    """Triangulate every face of `solid`.

    Args:
        solid: the shape.
        tolerance: chordal deviation in mm; by default 0.2% of the bounding-box diagonal,
            fine enough for curved faces to look smooth at 256 pixels.
        angular_tolerance: angular deviation in radians.
    """
    if tolerance is None:
        tolerance = 2e-3 * model_scale(solid)
    solid.mesh(tolerance, angular_tolerance)
    verts, tris, owner = [], [], []
    offset = 0
    for index, face in enumerate(solid.Faces()):
        loc = TopLoc_Location()
        poly = BRep_Tool.Triangulation_s(face.wrapped, loc)
        if poly is None:
            continue
        trsf = loc.Transformation()
        nodes = [poly.Node(i).Transformed(trsf) for i in range(1, poly.NbNodes() + 1)]
        verts.append(np.array([(p.X(), p.Y(), p.Z()) for p in nodes]))
        t = np.array([(tr.Value(1), tr.Value(2), tr.Value(3)) for tr in poly.Triangles()]) - 1
        if face.wrapped.Orientation() == TopAbs_REVERSED:
            t = t[:, ::-1]
        tris.append(t + offset)
        owner.append(np.full(len(t), index))
        offset += len(nodes)
    if not verts:
        raise ValueError("the shape has no faces to render")
    v = np.concatenate(verts)
    t = np.concatenate(tris).astype(np.int32)
    return FaceMesh(v, t, np.concatenate(owner).astype(np.int32), _vertex_normals(v, t))


def _vertex_normals(v: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Area-weighted average of the adjacent triangles' normals (within one face)."""
    tn = np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])
    n = np.zeros_like(v)
    for k in range(3):
        np.add.at(n, t[:, k], tn)
    length = np.linalg.norm(n, axis=1, keepdims=True)
    return n / np.where(length > 0, length, 1.0)
