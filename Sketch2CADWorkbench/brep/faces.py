# SPDX-License-Identifier: LGPL-2.1-or-later
"""Resolving a geometric face reference (`FaceRef`) against the current solid."""
from __future__ import annotations

from dataclasses import dataclass

import cadquery as cq
import numpy as np
from OCP.Bnd import Bnd_Box
from OCP.BRepBndLib import BRepBndLib
from OCP.BRepClass import BRepClass_FaceClassifier
from OCP.gp import gp_Pnt
from OCP.TopAbs import TopAbs_IN, TopAbs_ON

from .protocol import FaceRef, OperationError  # OperationError is imported from here too

# Normals within this angle (cosine) are taken as the same direction.
NORMAL_COS_TOL = 1.0 - 1e-6


@dataclass(frozen=True)
class ResolvedFace:
    """A planar face of the solid matched to a FaceRef.

    `shift` is how far (mm, along the normal) the face's plane lies from the
    reference point: 0 on a faithful replay, non-zero when an earlier step was
    edited and the face moved; operations translate their geometry by it.
    """

    face: cq.Face
    normal: np.ndarray
    shift: float

    @staticmethod
    def of(face: cq.Face) -> "ResolvedFace":
        """A planar face of the solid itself, as `resolve_face` finds it from the face's
        own `face_ref_of` (no shift): for callers that already hold the face."""
        return ResolvedFace(face, np.array(face.normalAt().toTuple()), 0.0)

    @property
    def offset(self) -> np.ndarray:
        """Translation that carries the reference's geometry onto this face's plane."""
        return self.normal * self.shift


def model_scale(solid: cq.Shape) -> float:
    """The bounding-box diagonal of a shape in mm; sets the geometric tolerances.

    OCCT's fast (not optimal) box: a scale for tolerances need not be tight, and the
    optimal box costs more than a Boolean.
    """
    box = Bnd_Box()
    BRepBndLib.Add_s(solid.wrapped, box, True)
    x0, y0, z0, x1, y1, z1 = box.Get()
    return float(np.sqrt((x1 - x0) ** 2 + (y1 - y0) ** 2 + (z1 - z0) ** 2))


def points_on_face(face: cq.Face, points: np.ndarray, tol: float,
                   boundary: bool = True) -> np.ndarray:
    """Which points (K, 3) of f's plane lie on f: (K,) bool.

    OCCT's face classifier (a third of the time of a distance query per point). With
    `boundary`, points within tol of f's edges count as on f; without, only strictly
    inside ones do.
    """
    states = (TopAbs_IN, TopAbs_ON) if boundary else (TopAbs_IN,)
    classifier = BRepClass_FaceClassifier()
    out = np.empty(len(points), bool)
    for i, p in enumerate(np.asarray(points, float)):
        classifier.Perform(face.wrapped, gp_Pnt(*map(float, p)), tol)
        out[i] = classifier.State() in states
    return out


def inside_face(face: cq.Face, point: np.ndarray) -> bool:
    """Whether a point of f's plane lies strictly inside f (holes excluded)."""
    return bool(points_on_face(face, np.asarray(point, float)[None], 1e-7, boundary=False)[0])


def planar_faces(solid: cq.Shape) -> list[tuple[cq.Face, np.ndarray, float]]:
    """Each planar face with its outward unit normal and plane offset n . p."""
    out = []
    for f in solid.Faces():
        if f.geomType() != "PLANE":
            continue
        n = np.array(f.normalAt().toTuple())
        p = np.array(f.Center().toTuple())
        out.append((f, n, float(n @ p)))
    return out


def resolve_face(solid: cq.Shape, ref: FaceRef, what: str = "face") -> ResolvedFace:
    """Find the planar face of `solid` that `ref` designates.

    The face whose plane holds ref.point and which contains it wins. If none does
    (an earlier step was edited and the face moved), the nearest face with the
    same normal whose outline still contains the point's projection is taken, if it
    lies within one model diagonal of the point.

    Raises:
        OperationError: no planar face of the solid matches the reference.
    """
    scale = model_scale(solid)
    tol = 1e-6 * max(scale, 1.0)
    n_ref = np.asarray(ref.normal, dtype=float)
    p_ref = np.asarray(ref.point, dtype=float)
    if not (np.isfinite(n_ref).all() and np.isfinite(p_ref).all()) \
            or abs(float(np.linalg.norm(n_ref)) - 1.0) > 1e-6:
        raise OperationError(f"{what} reference (point {ref.point}, normal {ref.normal}): "
                             "expected a finite point and a unit normal")
    best: tuple[cq.Face, np.ndarray, float] | None = None
    for face, n, offset in planar_faces(solid):
        if float(n @ n_ref) < NORMAL_COS_TOL:
            continue
        shift = offset - float(n @ p_ref)
        if abs(shift) > scale:
            continue
        projected = p_ref + n * shift
        if face.distance(cq.Vertex.makeVertex(*projected)) > tol:
            continue
        if best is None or abs(shift) < abs(best[2]):
            best = (face, n, shift)
    if best is None:
        raise OperationError(
            f"{what} reference (point {tuple(round(x, 4) for x in ref.point)}, normal "
            f"{tuple(round(x, 4) for x in ref.normal)}) no longer resolves: no planar face "
            "with that outward normal contains the point")
    face, n, shift = best
    if abs(shift) > tol:
        _refuse_inward_normal(solid, ref, p_ref, n_ref, tol, what)
    return ResolvedFace(face, n, 0.0 if abs(shift) <= tol else shift)


def _refuse_inward_normal(solid: cq.Shape, ref: FaceRef, p_ref: np.ndarray, n_ref: np.ndarray,
                          tol: float, what: str) -> None:
    """A point on a face whose outward normal is the opposite of ref's: the reference's
    normal points into the solid (it would otherwise match the face across the solid)."""
    for face, n, offset in planar_faces(solid):
        if float(n @ n_ref) <= -NORMAL_COS_TOL and abs(offset - float(n @ p_ref)) <= tol \
                and face.distance(cq.Vertex.makeVertex(*p_ref)) <= tol:
            raise OperationError(
                f"{what} reference (point {tuple(round(x, 4) for x in ref.point)}, normal "
                f"{tuple(round(x, 4) for x in ref.normal)}): the normal points into the "
                f"solid; the face there faces {tuple(round(float(x), 4) for x in n)}")


def face_ref_of(face: cq.Face) -> FaceRef:
    """A FaceRef for a planar face: its normal and a point strictly inside it."""
    n = face.normalAt()
    p = interior_point(face)
    return FaceRef(tuple(round(c, 9) for c in p), tuple(round(c, 12) for c in n.toTuple()))


def interior_point(face: cq.Face) -> tuple[float, float, float]:
    """A point inside a planar face, away from its edges (its centroid if inside)."""
    c = face.Center()
    if face.distance(cq.Vertex.makeVertex(*c.toTuple())) < 1e-9:
        return c.toTuple()
    # Non-convex face: sample the UV box and take the inside point farthest from the edges.
    u0, u1, v0, v1 = face.uvBounds()
    outline = cq.Compound.makeCompound(face.Edges())
    best, best_d = None, -1.0
    for u in np.linspace(u0, u1, 17)[1:-1]:
        for v in np.linspace(v0, v1, 17)[1:-1]:
            p = face.positionAt(u, v)
            vert = cq.Vertex.makeVertex(*p.toTuple())
            if face.distance(vert) > 1e-9:
                continue
            d = outline.distance(vert)
            if d > best_d:
                best, best_d = p.toTuple(), d
    if best is None:
        raise OperationError("face has no interior point (degenerate face)")
    return best
