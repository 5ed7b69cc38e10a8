# SPDX-License-Identifier: LGPL-2.1-or-later
"""Triangulating a B-rep solid for rendering, keeping which B-rep face each triangle is on.

OCCT's BRepMesh triangulates the faces; the triangulation is stored on the shape (as
OCCT always does), so a shape already meshed finely enough is not meshed again. OCCT's
IVtk converter then copies every face's triangles, nodes and surface normals into one
VTK mesh in C++, several times faster than reading the nodes one by one from Python.
"""

from __future__ import annotations

from dataclasses import dataclass

import cadquery as cq
import numpy as np
from OCP.Aspect import Aspect_TOL_SOLID
from OCP.BRepMesh import BRepMesh_IncrementalMesh
from OCP.BRepTools import BRepTools
from OCP.IVtk import IVtk_MeshType
from OCP.IVtkOCC import IVtkOCC_Shape, IVtkOCC_ShapeMesher
from OCP.IVtkVTK import IVtkVTK_ShapeData
from OCP.Prs3d import Prs3d_IsoAspect
from OCP.Quantity import Quantity_Color
from vtkmodules.util.numpy_support import vtk_to_numpy

from ..brep.faces import indexed_faces, model_scale

# Chordal deviation relative to the bounding-box diagonal: about half a pixel when the
# whole model fills a 256-pixel view.
REL_TOLERANCE = 2e-3
# Angular deviation (rad): BRepMesh must meet both limits, so this only refines small
# curved features; 0.35 rad keeps a circle's sagitta under 1.6% of its radius.
ANGULAR_TOLERANCE = 0.35
# A stored triangulation up to this factor coarser than asked is reused (see tessellate).
REUSE_SLACK = 1.25
# A view-driven tolerance is never finer than this (relative to the diagonal): a close-up
# of a large model must not produce a huge mesh.
MIN_REL_TOLERANCE = 2e-4


@dataclass(frozen=True)
class FaceMesh:
    """A triangle mesh of a solid, in world coordinates (mm).

    Vertices are not shared between B-rep faces, so vertex normals are smooth within a
    face and sharp across its edges. Positions pass through OCCT's float32 VTK export,
    so they are exact to about 1e-7 of their distance from the origin.

    Attributes:
        vertices: (V, 3) float64 positions.
        triangles: (T, 3) int32 vertex indices, counter-clockwise seen from outside.
        face_index: (T,) int32 index of each triangle's face in solid.Faces().
        normals: (T, 3) float64 outward unit normal of each triangle.
        vertex_normals: (V, 3) float64 outward unit surface normal at each vertex.
    """

    vertices: np.ndarray
    triangles: np.ndarray
    face_index: np.ndarray
    normals: np.ndarray
    vertex_normals: np.ndarray

    @property
    def diagonal(self) -> float:
        """The bounding-box diagonal of the vertices (mm)."""
        return float(np.linalg.norm(self.vertices.max(axis=0) - self.vertices.min(axis=0)))


def view_tolerance(model_size: float, pixel_size: float) -> float:
    """The chordal tolerance (mm) for a view: half a pixel, kept within
    [MIN_REL_TOLERANCE, REL_TOLERANCE] times the model size.

    Args:
        model_size: the model's bounding-box diagonal (mm).
        pixel_size: the view's pixel size (mm).
    """
    return float(
        np.clip(0.5 * pixel_size, MIN_REL_TOLERANCE * model_size, REL_TOLERANCE * model_size)
    )


def tessellate(
    solid: cq.Shape, tolerance: float | None = None, angular_tolerance: float = ANGULAR_TOLERANCE
) -> FaceMesh:
    """Triangulate every face of `solid`.

    Args:
        solid: the shape (a solid, or any shape with faces).
        tolerance: largest chordal deviation in mm; by default REL_TOLERANCE times the
            bounding-box diagonal. A triangulation already on the shape is reused when
            its deviation is at most REUSE_SLACK times this.
        angular_tolerance: largest angle (rad) between neighbouring segments' normals.
    Returns:
        The mesh; faces OCCT could not triangulate are left out.
    Raises:
        ValueError: a non-positive tolerance, or nothing to triangulate.
    """
    if tolerance is None:
        tolerance = REL_TOLERANCE * model_scale(solid)
    if not tolerance > 0 or not angular_tolerance > 0:
        raise ValueError(
            f"tolerances must be positive, got {tolerance} mm and {angular_tolerance} rad"
        )
    shape = solid.wrapped
    # BRepMesh records the deviation it reached, which on curved faces can exceed the
    # request by a few percent; without slack every call would mesh again.
    if not BRepTools.Triangulation_s(shape, REUSE_SLACK * tolerance):
        BRepMesh_IncrementalMesh(shape, tolerance, False, angular_tolerance, False)

    ivtk = IVtkOCC_Shape(shape)
    drawer = ivtk.Attributes()
    drawer.SetAutoTriangulation(False)  # use the triangulation just checked, never remesh
    no_isolines = Prs3d_IsoAspect(Quantity_Color(), Aspect_TOL_SOLID, 1.0, 0)
    drawer.SetUIsoAspect(no_isolines)
    drawer.SetVIsoAspect(no_isolines)
    data = IVtkVTK_ShapeData()
    IVtkOCC_ShapeMesher().Build(ivtk, data)
    pd = data.getVtkPolyData()

    polys = pd.GetPolys()
    conn = vtk_to_numpy(polys.GetConnectivityArray())
    if len(conn) == 0:
        raise ValueError("the shape has no faces to render")
    if not np.all(np.diff(vtk_to_numpy(polys.GetOffsetsArray())) == 3):
        raise RuntimeError("IVtk produced non-triangular face cells")
    # Cell data follow insertion order over vertices, lines and polygons alike; the
    # shaded-face cells, in that order, are exactly the polygons in polygon order.
    cells = pd.GetCellData()
    shaded = vtk_to_numpy(cells.GetArray("MESH_TYPES")) == int(IVtk_MeshType.MT_ShadedFace)
    sub_ids = vtk_to_numpy(cells.GetArray("SUBSHAPE_IDS"))[shaded]
    if len(sub_ids) * 3 != len(conn):
        raise RuntimeError("IVtk face cells and their sub-shape ids disagree")
    faces = indexed_faces(solid)
    lut = np.full(int(sub_ids.max()) + 1, -1, np.int32)
    for index in range(faces.Extent()):
        sid = ivtk.GetSubShapeId(faces.FindKey(index + 1))
        if sid < len(lut):
            lut[sid] = index
    face_index = lut[sub_ids]
    if (face_index < 0).any():
        raise RuntimeError("IVtk face cells refer to shapes that are not faces of the solid")

    # Drop the points IVtk made for edges and vertices.
    used, tris = np.unique(conn, return_inverse=True)
    points = vtk_to_numpy(pd.GetPoints().GetData())[used].astype(np.float64)
    vnormals = vtk_to_numpy(pd.GetPointData().GetArray("Normals"))[used].astype(np.float64)
    vnormals /= np.maximum(np.linalg.norm(vnormals, axis=1, keepdims=True), 1e-300)
    tris = tris.reshape(-1, 3).astype(np.int32)
    return FaceMesh(points, tris, face_index, _triangle_normals(points, tris, vnormals), vnormals)


def _triangle_normals(v: np.ndarray, t: np.ndarray, vn: np.ndarray) -> np.ndarray:
    """Unit geometric normals; a degenerate triangle takes its vertices' mean normal."""
    n = np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])
    length = np.linalg.norm(n, axis=1, keepdims=True)
    mean = vn[t].sum(axis=1)
    n = np.where(length > 1e-300, n / np.maximum(length, 1e-300), mean)
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
