# SPDX-License-Identifier: LGPL-2.1-or-later
"""Resolving a geometric face reference (`FaceRef`) against the current solid, planar or
curved (a cylinder's or cone's side, `CurvedSurface`)."""

from __future__ import annotations

from dataclasses import dataclass

import cadquery as cq
import numpy as np
from cadquery.occ_impl.shapes import geom_LUT_FACE
from OCP.Bnd import Bnd_Box
from OCP.BRep import BRep_Tool
from OCP.BRepAdaptor import BRepAdaptor_Curve, BRepAdaptor_Surface
from OCP.BRepBndLib import BRepBndLib
from OCP.BRepClass import BRepClass_FaceClassifier
from OCP.BRepExtrema import BRepExtrema_DistShapeShape
from OCP.GeomAbs import GeomAbs_Line, GeomAbs_Plane
from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf
from OCP.gp import gp_Pnt
from OCP.TopAbs import (
    TopAbs_EDGE,
    TopAbs_FACE,
    TopAbs_FORWARD,
    TopAbs_IN,
    TopAbs_ON,
    TopAbs_REVERSED,
)
from OCP.TopExp import TopExp, TopExp_Explorer
from OCP.TopoDS import TopoDS
from OCP.TopTools import TopTools_IndexedMapOfShape

from .geometry import plane_basis
from .protocol import FaceRef, OperationError, Surface  # OperationError is imported from here too

# Normals within this angle (cosine) are taken as the same direction.
NORMAL_COS_TOL = 1.0 - 1e-6
# A point within this share of the model's size (at least of 1 mm) of a face lies on it.
ON_FACE_REL = 1e-6
# OCCT's names of the surfaces a base face may lie on.
GEOM_TYPES = {Surface.PLANE: "PLANE", Surface.CYLINDER: "CYLINDER", Surface.CONE: "CONE"}
CURVED_GEOM_TYPES = (GEOM_TYPES[Surface.CYLINDER], GEOM_TYPES[Surface.CONE])


@dataclass(frozen=True)
class FaceFrame:
    """A planar face's plane, or a curved face's tangent plane at a point: origin (on the
    plane), outward unit normal n, in-plane u, v."""

    origin: np.ndarray
    normal: np.ndarray
    u: np.ndarray
    v: np.ndarray

    @staticmethod
    def of(face: cq.Face) -> FaceFrame:
        n = np.array(face.normalAt().toTuple())
        return FaceFrame(np.array(face.Center().toTuple()), n, *plane_basis(n))

    @staticmethod
    def tangent(face: cq.Face, ref: FaceRef) -> FaceFrame:
        """The tangent plane T of a curved f at a step's point p_f (`ref`: p_f and n_f
        there), in which its prism's polygon or sweep's c0 lies (brep/operators): u runs
        along the surface's generatrix through p_f, v around the surface."""
        surface = CurvedSurface.of(face)
        n = np.asarray(ref.normal, float)
        u = surface.axis - (surface.axis @ n) * n
        u /= np.linalg.norm(u)
        return FaceFrame(np.asarray(ref.point, float), n, u, np.cross(n, u))

    def to_2d(self, pts: np.ndarray) -> np.ndarray:
        q = np.atleast_2d(pts) - self.origin
        return np.stack([q @ self.u, q @ self.v], axis=1)

    def to_3d(self, q: np.ndarray) -> np.ndarray:
        q = np.atleast_2d(q)
        return self.origin + q[:, :1] * self.u + q[:, 1:2] * self.v


def is_curved(face: cq.Face) -> bool:
    """Whether f is a cylinder's or cone's side (else planar)."""
    return face.geomType() in CURVED_GEOM_TYPES


# A line's quadratic with a leading coefficient under this share of |direction|^2 is
# linear: the line runs along a cylinder's axis or a cone's generatrix.
LINEAR_REL = 1e-12


@dataclass(frozen=True)
class CurvedSurface:
    """The cylinder or cone a curved face lies on, and which side of it the solid is.

    The surface is the set of points at distance r(h) = radius + slope * h from the axis
    through `origin` along the unit vector `axis`, h being the height along `axis` above
    `origin` (mm): slope 0 for a cylinder, tan of the half-angle for a cone. `convex`:
    the face's outward normal points away from the axis (a boss's side; a bore's wall
    is not convex).
    """

    kind: Surface
    origin: np.ndarray
    axis: np.ndarray
    radius: float
    slope: float
    convex: bool

    @staticmethod
    def of(face: cq.Face) -> CurvedSurface:
        """The surface of a cylindrical or conical face (OCCT's gp_Cylinder / gp_Cone)."""
        kind = face.geomType()
        adaptor = BRepAdaptor_Surface(face.wrapped)  # also under a trimmed surface
        if kind == "CYLINDER":
            g, slope, surface = adaptor.Cylinder(), 0.0, Surface.CYLINDER
        elif kind == "CONE":
            g = adaptor.Cone()
            slope, surface = float(np.tan(g.SemiAngle())), Surface.CONE
        else:
            raise OperationError(f"a {kind.lower()} face is not a cylinder's or cone's side")
        origin = np.array(g.Location().Coord())
        axis = np.array(g.Axis().Direction().Coord())
        radius = float(g.RefRadius() if surface is Surface.CONE else g.Radius())
        u0, u1, v0, v1 = face.uvBounds()  # a point of the face (its centroid is on the axis)
        p = np.array(adaptor.Value(0.5 * (u0 + u1), 0.5 * (v0 + v1)).Coord())
        n = np.array(face.normalAt().toTuple())
        radial = (p - origin) - ((p - origin) @ axis) * axis
        return CurvedSurface(surface, origin, axis, radius, slope, bool(n @ radial > 0))

    def level(self, points: np.ndarray) -> np.ndarray:
        """Signed distance-like value (K,) of points (K, 3): > 0 outside the surface (away
        from the axis), 0 on it, < 0 inside."""
        rel = np.asarray(points, float) - self.origin
        h = rel @ self.axis
        across = np.linalg.norm(rel - np.outer(h, self.axis), axis=1)
        return across - (self.radius + self.slope * h)

    def radius_at(self, points: np.ndarray) -> np.ndarray:
        """r(h) at the height of each point (..., 3) along the axis (mm)."""
        return self.radius + self.slope * ((np.asarray(points, float) - self.origin) @ self.axis)

    def normals(self, points: np.ndarray) -> np.ndarray:
        """The face's outward unit normals (K, 3) at points (K, 3) of the surface: away
        from the axis on a convex face, toward it on a bore's wall (a cone's tilted by
        its slope)."""
        rel = np.asarray(points, float) - self.origin
        radial = rel - np.outer(rel @ self.axis, self.axis)
        radial /= np.linalg.norm(radial, axis=1, keepdims=True)
        n = radial - self.slope * self.axis  # the gradient of `level`
        n /= np.linalg.norm(n, axis=1, keepdims=True)
        return n if self.convex else -n

    def roots(
        self, points: np.ndarray, direction: np.ndarray, lo: float, hi: float
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Where the lines q + t direction (q: points (K, 3)) cross the surface for t in
        [lo, hi]: the line index (M,), t (M,), and whether the line enters the surface
        there (M,) (passes from outside to inside), ordered by line, then t.

        In closed form: along a line |rel_perp|^2 = r(h)^2 is a quadratic in t, whose
        roots with r(h) >= 0 (on a cone's own nappe) are the crossings; a line that only
        touches the surface does not cross it."""
        q = np.atleast_2d(np.asarray(points, float))
        direction = np.asarray(direction, float)
        rel = q - self.origin
        h0, da = rel @ self.axis, float(direction @ self.axis)
        p0 = rel - np.outer(h0, self.axis)  # across the axis at t = 0, and its rate in t
        dp = direction - da * self.axis
        r0 = self.radius + self.slope * h0
        a = float(dp @ dp) - (self.slope * da) ** 2
        b = 2.0 * (p0 @ dp - self.slope * da * r0)
        c = np.einsum("ij,ij->i", p0, p0) - r0**2
        k = np.arange(len(q))
        if abs(a) <= LINEAR_REL * float(direction @ direction):
            k = k[b != 0]  # along a cylinder's axis no crossing, along a cone's line one
            t = -c[k] / b[k]
        else:
            disc = b * b - 4.0 * a * c
            k = k[disc > 0]
            half = -0.5 * (b[k] + np.copysign(np.sqrt(disc[k]), b[k]))  # no cancellation
            k, t = np.concatenate([k, k]), np.concatenate([half / a, c[k] / half])
        keep = (t >= lo) & (t <= hi) & (self.radius_at(q[k] + t[:, None] * direction) >= 0)
        order = np.lexsort((t[keep], k[keep]))
        k, t = k[keep][order], t[keep][order]
        # entering where the quadratic (of `level`'s sign on the nappe) falls
        return k, t, 2.0 * a * t + b[k] < 0

    def crossings(self, points: np.ndarray, direction: np.ndarray, span: float) -> np.ndarray:
        """For each point q (K, 3), the t nearest 0 in [-span, span] where q + t direction
        crosses the surface: (K,), NaN where the line misses it within the span."""
        k, t, _ = self.roots(points, direction, -span, span)
        out = np.full(len(np.atleast_2d(points)), np.nan)
        nearest = np.lexsort((np.abs(t), k))  # per line, the smallest |t| first
        first = np.unique(k[nearest], return_index=True)[1]
        out[k[nearest][first]] = t[nearest][first]
        return out

    def solid(self, around: np.ndarray, extent: float) -> cq.Solid:
        """The solid the surface bounds (the points inside it), `extent` mm along the axis
        either side of the foot of `around`; a cone is cut off at its apex (`bounds`)."""
        base, r_lo, r_hi, length = self.bounds(around, extent)
        direction = cq.Vector(*self.axis)
        if self.slope == 0.0:
            return cq.Solid.makeCylinder(self.radius, length, cq.Vector(*base), direction)
        return cq.Solid.makeCone(r_lo, r_hi, length, cq.Vector(*base), direction)

    def bounds(self, around: np.ndarray, extent: float) -> tuple[np.ndarray, float, float, float]:
        """The solid of `solid` as a cylinder or cone along the axis: its base centre (3,),
        radius there and at the far end, and length (mm)."""
        h0 = float((np.asarray(around, float) - self.origin) @ self.axis)
        lo, hi = h0 - extent, h0 + extent
        r_lo, r_hi = self.radius + self.slope * lo, self.radius + self.slope * hi
        if self.slope != 0.0:  # stop at the apex, where r(h) = 0
            apex = -self.radius / self.slope
            if r_lo < 0:
                lo, r_lo = apex, 0.0
            if r_hi < 0:
                hi, r_hi = apex, 0.0
        return self.origin + lo * self.axis, r_lo, r_hi, hi - lo


@dataclass(frozen=True)
class ResolvedFace:
    """A face of the solid matched to a FaceRef.

    `shift` is how far (mm, along the normal) the face lies from the reference point:
    0 on a faithful replay, non-zero when an earlier step was edited and the face moved
    (a plane along its normal, a cylinder's radius); operations translate their
    geometry by it. `surface` is None for a planar face and the cylinder or cone
    otherwise; `point` is the reference point moved onto the face: on a curved face,
    the point whose tangent plane the step's geometry lies in.
    """

    face: cq.Face
    normal: np.ndarray
    shift: float
    surface: CurvedSurface | None = None
    point: np.ndarray | None = None

    @staticmethod
    def of(face: cq.Face) -> ResolvedFace:
        """A planar face of the solid itself, as `resolve_face` finds it from the face's
        own `face_ref_of` (no shift): for callers that already hold the face. Its normal
        is read as `planar_faces` reads it, so that both give the same result to the bit."""
        plane = _plane(face.wrapped)
        if plane is None:
            raise ValueError("ResolvedFace.of takes a planar face")
        return ResolvedFace(face, plane[0], 0.0)

    @property
    def offset(self) -> np.ndarray:
        """Translation that carries the reference's geometry onto this face's plane."""
        return self.normal * self.shift

    @property
    def plane_point(self) -> np.ndarray:
        """A point of f's plane: on a curved f, of its tangent plane at the step's point."""
        if self.point is not None:
            return self.point
        return np.array(self.face.Center().toTuple())


def model_scale(solid: cq.Shape) -> float:
    """The bounding-box diagonal of a shape in mm; sets the geometric tolerances.

    OCCT's fast (not optimal) box: a scale for tolerances need not be tight, and the
    optimal box costs more than a Boolean.
    """
    lo, hi = model_box(solid)
    return float(np.linalg.norm(hi - lo))


def model_box(solid: cq.Shape) -> tuple[np.ndarray, np.ndarray]:
    """OCCT's fast bounding box of a shape (its lowest and highest corners, mm): it may
    exceed the shape a little; cadquery's `BoundingBox()` is tight but takes a fifth
    of a second on a solid with curved faces."""
    box = Bnd_Box()
    BRepBndLib.Add_s(solid.wrapped, box, True)
    x0, y0, z0, x1, y1, z1 = box.Get()
    return np.array([x0, y0, z0]), np.array([x1, y1, z1])


def indexed_faces(shape: cq.Shape) -> TopTools_IndexedMapOfShape:
    """The faces of a shape in the order of shape.Faces() (index i + 1 there is face i),
    without wrapping every face in a cadquery object as Faces() does."""
    faces = TopTools_IndexedMapOfShape()
    TopExp.MapShapes_s(shape.wrapped, TopAbs_FACE, faces)
    return faces


def face_kinds(shape: cq.Shape) -> list[str]:
    """Each face's surface kind as cadquery's geomType() names it ("PLANE", "CYLINDER",
    ...), in the order of shape.Faces(), without wrapping every face as Faces() does."""
    faces = indexed_faces(shape)
    return [
        geom_LUT_FACE[BRepAdaptor_Surface(TopoDS.Face_s(faces.FindKey(i))).GetType()]
        for i in range(1, faces.Extent() + 1)
    ]


def plane_normals(shape: cq.Shape) -> dict[int, np.ndarray]:
    """The outward unit normal of each planar face (as face.normalAt() gives it: the
    plane's u x v, reversed with the face), by its index in shape.Faces()."""
    faces, out = indexed_faces(shape), {}
    for i in range(faces.Extent()):
        plane = _plane(TopoDS.Face_s(faces.FindKey(i + 1)))
        if plane is not None:
            out[i] = plane[0]
    return out


def _plane(face) -> tuple[np.ndarray, float] | None:
    """A planar TopoDS face's outward unit normal and plane offset n . p, read off its
    plane (no area integral: resolving a face on a solid of thousands of faces would
    cost more than the Boolean); None for a curved face."""
    surface = BRepAdaptor_Surface(face)
    if surface.GetType() != GeomAbs_Plane:
        return None
    frame = surface.Plane().Position()
    # u x v: the frame's main direction, reversed in a left-handed frame
    sign = (1.0 if frame.Direct() else -1.0) * (
        -1.0 if face.Orientation() == TopAbs_REVERSED else 1.0
    )
    n = tuple(sign * x for x in frame.Direction().Coord())
    offset = sum(a * b for a, b in zip(n, frame.Location().Coord(), strict=False))
    return np.array(n), float(offset)


def face_at(shape: cq.Shape, index: int) -> cq.Face:
    """shape.Faces()[index] (the same face), without wrapping every face as Faces() does.

    Raises:
        IndexError: the shape has no face `index`.
    """
    faces = indexed_faces(shape)
    if not 0 <= index < faces.Extent():
        raise IndexError(f"face {index} of a shape with {faces.Extent()} faces")
    return cq.Face(faces.FindKey(index + 1))


def base_face_index(solid: cq.Shape, face: cq.Face) -> int:
    """The index in solid.Faces() of a face of it (the renderer's face IDs; for the
    base face f, of resolve_face(context solid, op.face).face).

    Raises:
        ValueError: the face is not one of the solid's.
    """
    index = indexed_faces(solid).FindIndex(face.wrapped)  # matches as isSame does
    if index == 0:
        raise ValueError("the face is not a face of the solid")
    return index - 1


def points_on_face(
    face: cq.Face, points: np.ndarray, tol: float, boundary: bool = True
) -> np.ndarray:
    """Which points (K, 3) of f's plane lie on f: (K,) bool.

    With `boundary`, points within tol of f's edges count as on f; without, only
    strictly inside ones do. On a planar f whose sides are all straight this is told in
    f's plane: by counting crossings of the sides (even-odd) and by the distance to the
    nearest side, within tol plus the sides' own tolerance (`_straight_sides`), which
    is OCCT's classifier's answer but for a few points within 2 tol of a side, where
    its band is a little wider, without a call per point. Other
    faces go to OCCT's face classifier, point by point.
    """
    points = np.asarray(points, float).reshape(-1, 3)
    sides = _straight_sides(face)
    if sides is None:
        return _classify(face, points, tol, boundary)
    origin, axes, ends, own_tol = sides
    q = (points - origin) @ axes.T  # (K, 2) in f's plane
    a, b = ends[:, 0], ends[:, 1]  # (E, 2) each
    ab = b - a
    rel = q[:, None, :] - a[None]  # (K, E, 2)
    t = np.clip((rel * ab).sum(axis=2) / np.maximum((ab * ab).sum(axis=1), 1e-300), 0.0, 1.0)
    gap = np.hypot(*np.moveaxis(rel - t[..., None] * ab, 2, 0)).min(axis=1)
    # even-odd count of the sides crossing the ray from each point along +u, half open
    # at the ends so that a ray through a vertex counts it once
    above_a, above_b = a[None, :, 1] > q[:, None, 1], b[None, :, 1] > q[:, None, 1]
    straddles = above_a != above_b
    with np.errstate(divide="ignore", invalid="ignore"):
        x = a[None, :, 0] + (q[:, None, 1] - a[None, :, 1]) * ab[None, :, 0] / ab[None, :, 1]
    inside = (straddles & (q[:, None, 0] < x)).sum(axis=1) % 2 == 1
    on_sides = gap <= tol + own_tol
    return inside | on_sides if boundary else inside & ~on_sides


def _classify(face: cq.Face, points: np.ndarray, tol: float, boundary: bool) -> np.ndarray:
    """`points_on_face` by OCCT's classifier, point by point."""
    states = (TopAbs_IN, TopAbs_ON) if boundary else (TopAbs_IN,)
    classifier = BRepClass_FaceClassifier()
    out = np.empty(len(points), bool)
    for i, p in enumerate(points):
        classifier.Perform(face.wrapped, gp_Pnt(*map(float, p)), tol)
        out[i] = classifier.State() in states
    return out


def _straight_sides(face: cq.Face) -> tuple[np.ndarray, np.ndarray, np.ndarray, float] | None:
    """A planar face's sides, when all are straight and bound it (forward or reversed):
    its plane's origin (3,) and (u, v) axes (2, 3), each side's end vertices in them
    (E, 2, 2), and the largest tolerance of its edges and vertices; else None.

    The ends are the vertices' points, which the sides meeting there share, so the
    outline closes exactly and a count of crossings is exact for it; the true sides lie
    within their tolerance of it.
    """
    surface = BRepAdaptor_Surface(face.wrapped)
    if surface.GetType() != GeomAbs_Plane:
        return None
    frame = surface.Plane().Position()
    origin = np.array(frame.Location().Coord())
    axes = np.array([frame.XDirection().Coord(), frame.YDirection().Coord()])
    ends, own_tol = [], 0.0
    explorer = TopExp_Explorer(face.wrapped, TopAbs_EDGE)
    while explorer.More():
        edge = TopoDS.Edge_s(explorer.Current())
        explorer.Next()
        if (
            edge.Orientation() not in (TopAbs_FORWARD, TopAbs_REVERSED)
            or BRepAdaptor_Curve(edge).GetType() != GeomAbs_Line
        ):
            return None
        vertices = (TopExp.FirstVertex_s(edge), TopExp.LastVertex_s(edge))
        ends.append([BRep_Tool.Pnt_s(v).Coord() for v in vertices])
        own_tol = max(
            own_tol, BRep_Tool.Tolerance_s(edge), *(BRep_Tool.Tolerance_s(v) for v in vertices)
        )
    if not ends:
        return None
    return origin, axes, (np.array(ends) - origin) @ axes.T, own_tol


def inside_face(face: cq.Face, point: np.ndarray) -> bool:
    """Whether a point of f's plane lies strictly inside f (holes excluded)."""
    return bool(points_on_face(face, np.asarray(point, float)[None], 1e-7, boundary=False)[0])


def planar_faces(solid: cq.Shape) -> list[tuple[cq.Face, np.ndarray, float]]:
    """Each planar face with its outward unit normal and plane offset n . p."""
    out = []
    for f in solid.Faces():
        plane = _plane(f.wrapped)
        if plane is not None:
            out.append((f, *plane))
    return out


def resolve_face(solid: cq.Shape, ref: FaceRef, what: str = "face") -> ResolvedFace:
    """Find the face of `solid` that `ref` designates.

    A planar reference: the face whose plane holds ref.point and which contains it
    wins. If none does (an earlier step was edited and the face moved), the nearest
    face with the same normal whose outline still contains the point's projection is
    taken, if it lies within one model diagonal of the point. A curved reference:
    `resolve_curved_face`.

    Raises:
        OperationError: no face of the solid matches the reference.
    """
    scale = model_scale(solid)
    tol = ON_FACE_REL * max(scale, 1.0)
    n_ref = np.asarray(ref.normal, dtype=float)
    p_ref = np.asarray(ref.point, dtype=float)
    if (
        not (np.isfinite(n_ref).all() and np.isfinite(p_ref).all())
        or abs(float(np.linalg.norm(n_ref)) - 1.0) > 1e-6
    ):
        raise OperationError(
            f"{what} reference (point {ref.point}, normal {ref.normal}): "
            "expected a finite point and a unit normal"
        )
    if ref.surface.curved:
        return resolve_curved_face(solid, ref, scale, tol, what)
    best: tuple[cq.Face, np.ndarray, float] | None = None
    for face, n, offset in planar_faces(solid):
        if float(n @ n_ref) < NORMAL_COS_TOL:
            continue
        shift = offset - float(n @ p_ref)
        if abs(shift) > scale:
            continue
        projected = p_ref + n * shift
        if _off_box(face, projected, tol) or face.distance(cq.Vertex.makeVertex(*projected)) > tol:
            continue
        if best is None or abs(shift) < abs(best[2]):
            best = (face, n, shift)
    if best is None:
        raise OperationError(
            f"{what} reference (point {tuple(round(x, 4) for x in ref.point)}, normal "
            f"{tuple(round(x, 4) for x in ref.normal)}) no longer resolves: no planar face "
            "with that outward normal contains the point"
        )
    face, n, shift = best
    if abs(shift) > tol:
        _refuse_inward_normal(solid, ref, p_ref, n_ref, tol, what)
    return ResolvedFace(face, n, 0.0 if abs(shift) <= tol else shift)


def _off_box(face: cq.Face, point: np.ndarray, tol: float) -> bool:
    """Whether a point lies farther than tol from a face's bounding box, so from the face:
    told before OCCT's exact distance, which on a solid of many faces would otherwise be
    taken to every face with the reference's normal."""
    box = Bnd_Box()
    BRepBndLib.Add_s(face.wrapped, box, False)
    box.Enlarge(tol)
    return box.IsOut(gp_Pnt(*map(float, point)))


def resolve_curved_face(
    solid: cq.Shape, ref: FaceRef, scale: float, tol: float, what: str
) -> ResolvedFace:
    """The cylindrical or conical face `ref` designates: the face of that kind that holds
    ref.point with ref.normal as its outward normal there; if none does (an earlier step
    was edited: a sweep's radius changed), the nearest such face along the line through
    the point along the normal, within one model diagonal, where the face's normal is
    the same (on a cylinder, the line through the axis: a radius edit moves the point
    radially). A point still on the face after an edit moved the face along its axis
    stays where it is, as a point on a planar face does.

    Raises:
        OperationError: no face of that kind matches the reference.
    """
    n_ref = np.asarray(ref.normal, dtype=float)
    p_ref = np.asarray(ref.point, dtype=float)
    best: tuple[cq.Face, float, CurvedSurface] | None = None
    for face in solid.Faces():
        if face.geomType() != GEOM_TYPES[ref.surface]:
            continue
        surface = CurvedSurface.of(face)
        (t,) = surface.crossings(p_ref[None], n_ref, scale)
        if np.isnan(t) or (best is not None and abs(t) >= abs(best[1])):
            continue
        at = p_ref + t * n_ref
        if face.distance(cq.Vertex.makeVertex(*at)) > tol:
            continue
        if float(np.array(face.normalAt(cq.Vector(*at)).toTuple()) @ n_ref) < NORMAL_COS_TOL:
            continue
        best = (face, 0.0 if abs(t) <= tol else float(t), surface)
    if best is None:
        raise OperationError(
            f"{what} reference (point {tuple(round(x, 4) for x in ref.point)}, normal "
            f"{tuple(round(x, 4) for x in ref.normal)}) no longer resolves: no "
            f"{ref.surface.value} face has that outward normal at the point or along the "
            "line through it"
        )
    face, shift, surface = best
    return ResolvedFace(face, n_ref, shift, surface, p_ref + shift * n_ref)


def _refuse_inward_normal(
    solid: cq.Shape, ref: FaceRef, p_ref: np.ndarray, n_ref: np.ndarray, tol: float, what: str
) -> None:
    """A point on a face whose outward normal is the opposite of ref's: the reference's
    normal points into the solid (it would otherwise match the face across the solid)."""
    for face, n, offset in planar_faces(solid):
        if (
            float(n @ n_ref) <= -NORMAL_COS_TOL
            and abs(offset - float(n @ p_ref)) <= tol
            and face.distance(cq.Vertex.makeVertex(*p_ref)) <= tol
        ):
            raise OperationError(
                f"{what} reference (point {tuple(round(x, 4) for x in ref.point)}, normal "
                f"{tuple(round(x, 4) for x in ref.normal)}): the normal points into the "
                f"solid; the face there faces {tuple(round(float(x), 4) for x in n)}"
            )


def face_ref_of(face: cq.Face) -> FaceRef:
    """A FaceRef for a planar face: its normal and a point strictly inside it."""
    n = face.normalAt()
    p = interior_point(face)
    return FaceRef(tuple(round(c, 9) for c in p), tuple(round(c, 12) for c in n.toTuple()))


def face_ref_at(face: cq.Face, point) -> FaceRef:
    """A FaceRef for a step standing at `point` on a face of any kind: the point moved
    onto the face's surface (onto the face itself when that lies beyond its edges), the
    outward normal there, and the surface's kind.

    Raises:
        OperationError: the face is neither planar, cylindrical nor conical.
    """
    kinds = {v: k for k, v in GEOM_TYPES.items()}
    if face.geomType() not in kinds:
        raise OperationError(
            f"a base face must be planar, cylindrical or conical, not {face.geomType().lower()}"
        )
    at = cq.Vector(*map(float, point))
    projected = GeomAPI_ProjectPointOnSurf(at.toPnt(), BRep_Tool.Surface_s(face.wrapped))
    p = projected.NearestPoint().Coord() if projected.NbPoints() else at.toTuple()
    vertex = cq.Vertex.makeVertex(*p)
    if face.distance(vertex) > ON_FACE_REL * max(model_scale(face), 1.0):
        # beyond the face's edges on its surface (the mean of an outline around a cone's
        # narrow end): its nearest point of the face, where the reference resolves
        extrema = BRepExtrema_DistShapeShape(vertex.wrapped, face.wrapped)
        p = extrema.PointOnShape2(1).Coord()
        at = cq.Vector(*p)
    n = face.normalAt(at)
    return FaceRef(
        tuple(round(float(c), 9) for c in p),
        tuple(round(c, 12) for c in n.toTuple()),
        kinds[face.geomType()],
    )


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
