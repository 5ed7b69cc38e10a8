# SPDX-License-Identifier: LGPL-2.1-or-later
"""Rounds and chamfers: the edges a bevel follows, and OCCT's fillet and chamfer on them.

A bevel drawn across an edge (`Bevel.across`) names a planar face f on one side of the
edge and the point c of the edge that its profile l crosses, in the plane normal to the
edge there. `round_place` finds that edge on the solid as it is now (the edge of f
nearest c, c moved onto it), the face on its other side, and the set of edges the step
follows (`EdgeSet`): the edge itself, its tangent-continuous chain, or the whole wire of
f's outline that holds it. A fillet or chamfer is built by OCCT on every edge of the set
(`fillet_or_chamfer`); OCCT itself carries a fillet or chamfer on along the tangent
chain of each edge it is given. A freeform l is cut along one straight edge or revolved
around one circular rim (`profile_tool`); along a chain of several edges or an outline
it is refused, as OCCT has no operation that sweeps a freeform section around corners
of a chain. Points are world millimetres.
"""

from __future__ import annotations

from dataclasses import dataclass

import cadquery as cq
import numpy as np
from OCP.BRepFilletAPI import BRepFilletAPI_MakeChamfer, BRepFilletAPI_MakeFillet
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
from OCP.TopExp import TopExp
from OCP.TopoDS import TopoDS
from OCP.TopTools import TopTools_IndexedDataMapOfShapeListOfShape

from .apart import built_apart
from .faces import (
    CURVED_GEOM_TYPES,
    CurvedSurface,
    OperationError,
    ResolvedFace,
    points_on_face,
)
from .geometry import point_text, unit
from .protocol import Bevel, EdgeSet

# Two edges meeting at a vertex continue each other (one tangent chain) when the cosine of
# the angle between their directions there exceeds this: OCCT's own chains are G1 to
# its angular tolerance, far inside it (docs/measurements.md, brep rounds.TANGENT_COS).
TANGENT_COS = 0.999
# OCCT rounds the edges of the models sketched here well within a second; a fillet or
# chamfer over several edges still building after this long is looping and is refused
# (docs/measurements.md, rounds.FILLET_TIMEOUT_S).
FILLET_TIMEOUT_S = 20.0


@dataclass(frozen=True)
class EdgeSide:
    """An edge of the solid at a point: the point on it, the unit tangent there, and the
    two faces it bounds (`first` is f, or the face on l(0)'s side)."""

    edge: cq.Edge
    point: np.ndarray
    tangent: np.ndarray
    first: cq.Face
    second: cq.Face


@dataclass(frozen=True)
class RoundPlace:
    """Where a bevel across an edge is on the solid now: the drawn edge at c, l's control
    points (4, 3) moved with c, and the edges of its set."""

    side: EdgeSide
    profile: np.ndarray
    edges: list[cq.Edge]


def edge_faces(solid: cq.Shape) -> TopTools_IndexedDataMapOfShapeListOfShape:
    """OCCT's map from each edge of the solid to the faces it bounds."""
    found = TopTools_IndexedDataMapOfShapeListOfShape()
    TopExp.MapShapesAndAncestors_s(solid.wrapped, TopAbs_EDGE, TopAbs_FACE, found)
    return found


def faces_of(faces_map: TopTools_IndexedDataMapOfShapeListOfShape, edge: cq.Edge) -> list[cq.Face]:
    """The distinct faces an edge bounds (one for a seam, two for an edge between faces)."""
    out: list[cq.Face] = []
    for shape in faces_map.FindFromKey(edge.wrapped):
        if not any(f.wrapped.IsSame(shape) for f in out):
            out.append(cq.Face(TopoDS.Face_s(shape)))
    return out


def point_on_edge(edge: cq.Edge, point: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The point of `edge` nearest `point` and the edge's unit tangent there."""
    try:
        t = edge.paramAt(cq.Vector(*map(float, point)))
    except Exception:  # beyond both ends OCCT projects onto no point of the edge
        start, end = (np.array(p.toTuple()) for p in (edge.startPoint(), edge.endPoint()))
        nearer_end = np.linalg.norm(end - point) < np.linalg.norm(start - point)
        t = edge.paramAt(1.0 if nearer_end else 0.0)
    at = np.array(edge.positionAt(t, mode="parameter").toTuple())
    return at, unit(np.array(edge.tangentAt(t, mode="parameter").toTuple()))


def _side(
    solid: cq.Shape, faces_map, edge: cq.Edge, point: np.ndarray, first: cq.Face, what: str
) -> EdgeSide:
    faces = faces_of(faces_map, edge)
    others = [f for f in faces if not f.wrapped.IsSame(first.wrapped)]
    if len(faces) != 2 or len(others) != 1:
        raise OperationError(f"bevel: {what} is not an edge between two faces of the solid")
    at, tangent = point_on_edge(edge, point)
    return EdgeSide(edge, at, tangent, first, others[0])


def round_place(solid: cq.Shape, rf: ResolvedFace, op: Bevel, scale: float) -> RoundPlace:
    """The edge l is drawn across, found again on the solid now, and the edges its set
    holds.

    The edge is the one of f's outline nearest c; when an earlier step moved it, c moves
    onto it and l with c.

    Raises:
        OperationError: f is curved, c lies inside f, or l does not lie across the edge
            (its plane normal to the edge at c, l(0) on f), naming the field.
    """
    if rf.surface is not None:
        raise OperationError(
            f"bevel: face f is the side of a {rf.surface.kind.value}; a profile across an "
            "edge names the planar face on one side of the edge as f"
        )
    c = np.asarray(op.corner, float) + rf.offset
    drawn, gap = nearest_edge(rf.face, c)
    tol = 1e-6 * scale
    if gap > tol and points_on_face(rf.face, c[None], tol, boundary=False)[0]:
        raise OperationError(
            f"bevel: corner c {point_text(c)} lies inside face f, not on its outline; c must "
            "be the point of an edge of f that profile l crosses"
        )
    faces_map = edge_faces(solid)
    side = _side(solid, faces_map, drawn, c, rf.face, f"the edge of f at corner c {point_text(c)}")
    ctrl = np.asarray(op.profile, float) + rf.offset + (side.point - c)
    off_plane = np.abs((ctrl - side.point) @ side.tangent).max()
    if off_plane > 1e-3 * scale:
        raise OperationError(
            f"bevel: profile l lies {off_plane:.4g} mm off the plane normal to the edge at "
            f"corner c {point_text(side.point)}; l is drawn across the edge, from f to the face "
            "beyond"
        )
    if abs(float((ctrl[0] - side.point) @ rf.normal)) > 1e-3 * scale:
        raise OperationError(
            f"bevel: profile l starts {point_text(ctrl[0])} off face f's plane; l(0) lies on f"
        )
    return RoundPlace(side, ctrl, edge_set(solid, faces_map, rf.face, drawn, op.edges))


def traces(face: cq.Face, c: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The lines (unit directions, either way; (K, 3)) of `face` across an edge at its
    points c (K, 3) where its tangents are t (K, 3), in the plane normal to the edge:
    perpendicular to the edge in the face's tangent plane (a plane's line, a cylinder's
    or cone's generatrix)."""
    kind = face.geomType()
    if kind == "PLANE":
        n = np.broadcast_to(np.array(face.normalAt().toTuple()), c.shape)
    elif kind in CURVED_GEOM_TYPES:
        n = CurvedSurface.of(face).normals(c)
    else:  # a fillet's or a freeform face: OCCT's normal at each point
        n = np.array([face.normalAt(cq.Vector(*map(float, p))).toTuple() for p in c])
    u = np.cross(t, n)
    return u / np.linalg.norm(u, axis=-1, keepdims=True)


def into_face(face: cq.Face, c: np.ndarray, t: np.ndarray, step: float) -> np.ndarray | None:
    """The unit direction from c, a point of an edge of `face` where the edge's tangent
    is t, into the face across the edge (`traces`, the way that a step of `step` mm
    stays on the face); None when neither way does."""
    u = traces(face, c[None], t[None])[0]
    for sign in (1.0, -1.0):
        if face.distance(cq.Vertex.makeVertex(*(c + sign * step * u))) < 1e-2 * step:
            return sign * u
    return None


def nearest_edge(face: cq.Face, point: np.ndarray) -> tuple[cq.Edge, float]:
    """The edge of a face's outline nearest `point`, and how far it is (mm)."""
    at = cq.Vertex.makeVertex(*map(float, point))
    gaps = [(e.distance(at), i) for i, e in enumerate(face.Edges())]
    gap, i = min(gaps)
    return face.Edges()[i], gap


def far_copy(edge: cq.Edge, c: np.ndarray, ctrl: np.ndarray, back: bool = False) -> np.ndarray:
    """Where a designer draws the profile a second time, l' (its points (K, 3)): at the far
    end of a straight edge from c, across a circular rim (l turned half round its axis);
    l itself on other edges. `back`: the inverse, from l' to l."""
    if edge.geomType() == "LINE":
        ends = [np.array(p.toTuple()) for p in (edge.startPoint(), edge.endPoint())]
        far = max(ends, key=lambda e: float(np.linalg.norm(e - c)))
        return ctrl + (c - far if back else far - c)
    if edge.geomType() == "CIRCLE":  # a half turn is its own inverse
        center = np.array(edge.arcCenter().toTuple())
        axis = unit(np.array(edge.normal().toTuple()))
        rel = ctrl - center
        along = np.outer(rel @ axis, axis)
        return center + along - (rel - along)
    return ctrl


def crease_side(solid: cq.Shape, c: np.ndarray, crease: np.ndarray, a: np.ndarray) -> EdgeSide:
    """The solid's crease from c along `crease`, its faces ordered so that the first holds
    the direction `a` from the crease (l(0)'s side).

    Raises:
        OperationError: no straight edge of the solid runs there.
    """
    mid = c + crease / 2
    scale = float(np.linalg.norm(crease))
    found = [
        e
        for e in solid.Edges()
        if e.geomType() == "LINE"
        and e.distance(cq.Vertex.makeVertex(*map(float, mid))) < 1e-6 * scale
    ]
    if not found:
        raise OperationError(
            f"bevel: no edge of the solid runs along the crease from c {point_text(c)}"
        )
    faces = faces_of(edge_faces(solid), found[0])
    if len(faces) != 2:
        raise OperationError(f"bevel: the crease from c {point_text(c)} is not between two faces")
    probe = mid + 1e-3 * scale * a
    near = [f.distance(cq.Vertex.makeVertex(*map(float, probe))) for f in faces]
    first, second = (faces[0], faces[1]) if near[0] <= near[1] else (faces[1], faces[0])
    return EdgeSide(found[0], c, unit(crease), first, second)


def edge_set(
    solid: cq.Shape, faces_map, face: cq.Face, drawn: cq.Edge, which: EdgeSet
) -> list[cq.Edge]:
    """The edges a bevel follows: the drawn edge, its tangent chain, or the wire of f's
    outline that holds it (`EdgeSet`), the drawn edge first."""
    if which is EdgeSet.OUTLINE:
        wire = next(
            w for w in face.Wires() if any(e.wrapped.IsSame(drawn.wrapped) for e in w.Edges())
        )
        rest = [e for e in wire.Edges() if not e.wrapped.IsSame(drawn.wrapped)]
        return [drawn, *rest]
    if which is EdgeSet.DRAWN:
        return [drawn]
    return tangent_chain(solid, faces_map, drawn)


def tangent_chain(solid: cq.Shape, faces_map, drawn: cq.Edge) -> list[cq.Edge]:
    """The edges between two faces that continue `drawn` without a kink, through each of
    their vertices, the drawn edge first (seams, which bound one face, never join)."""
    candidates = [e for e in solid.Edges() if len(faces_of(faces_map, e)) == 2]
    chain, todo = [drawn], [drawn]
    while todo:
        edge = todo.pop()
        for vertex in edge.Vertices():
            p = np.array(vertex.toTuple())
            for other in candidates:
                if any(other.wrapped.IsSame(e.wrapped) for e in chain):
                    continue
                if other.distance(vertex) > 1e-7 * max(1.0, float(np.abs(p).max())):
                    continue
                t1 = point_on_edge(edge, p)[1]
                t2 = point_on_edge(other, p)[1]
                if abs(float(t1 @ t2)) > TANGENT_COS:
                    chain.append(other)
                    todo.append(other)
    return chain


def fillet_or_chamfer(solid: cq.Shape, op: Bevel, place: RoundPlace) -> cq.Shape:
    """The solid with OCCT's constant-radius fillet (op.radius) or two-distance chamfer
    (op.distances, d1 measured on each edge's face on f's side) on the place's edges
    (errors: as `fillet_or_chamfer_edges`)."""
    faces = []
    if op.distances is not None:
        faces_map = edge_faces(solid)
        faces = [face_on_side(faces_map, e, place.side.first) for e in place.edges]
    return fillet_or_chamfer_edges(solid, place.edges, op.radius, op.distances, faces)


def fillet_or_chamfer_edges(
    solid: cq.Shape,
    edges: list[cq.Edge],
    radius: float | None,
    distances: tuple[float, float] | None,
    faces: list[cq.Face],
) -> cq.Shape:
    """The solid with the edges rounded by `radius` or, where `distances` are given,
    chamfered: d1 on each edge's face in `faces`, d2 on its other face.

    Raises:
        OperationError: OCCT cannot build it (a radius or distance too large for the
            faces beside an edge, a chain it cannot follow), naming the field.
    """
    if distances is not None:
        d1, d2 = distances
        what = f"chamfer {len(edges)} edge(s) with distances = [{d1:g}, {d2:g}] mm"
    else:
        what = f"fillet {len(edges)} edge(s) with radius = {radius:g} mm"

    def build() -> cq.Shape | None:
        maker: BRepFilletAPI_MakeFillet | BRepFilletAPI_MakeChamfer
        if distances is not None:
            maker = BRepFilletAPI_MakeChamfer(solid.wrapped)
            for e, face in zip(edges, faces, strict=True):
                maker.Add(*distances, e.wrapped, face.wrapped)
        else:
            maker = BRepFilletAPI_MakeFillet(solid.wrapped)
            for e in edges:
                maker.Add(radius, e.wrapped)
        try:
            maker.Build()
            return cq.Shape.cast(maker.Shape()) if maker.IsDone() else None
        except Exception:  # OCCT raises StdFail_NotDone and kin on a failed fillet
            return None

    # OCCT's fillet around several edges (an outline of lines and arcs) can end the
    # process; one edge, the common bevel, is built here, at no cost of a fork
    got = built_apart(build, FILLET_TIMEOUT_S) if len(edges) > 1 else build()
    if got is None:
        raise OperationError(
            f"bevel: OCCT cannot {what}: too large for the faces beside an edge, or an edge "
            "chain it cannot follow"
        )
    return got


def edges_at(solid: cq.Shape, points: np.ndarray) -> list[cq.Edge]:
    """The edge of the solid nearest each point (K, 3)."""
    edges = solid.Edges()
    out = []
    for p in points:
        at = cq.Vertex.makeVertex(*map(float, p))
        out.append(min(edges, key=lambda e: e.distance(at)))
    return out


def face_on_side(faces_map, edge: cq.Edge, first: cq.Face) -> cq.Face:
    """Of the faces an edge bounds, f itself, or else the one whose normal is nearest
    f's (the edge's face on f's side; the far one stands across f)."""
    faces = faces_of(faces_map, edge)
    same = [f for f in faces if f.wrapped.IsSame(first.wrapped)]
    if same:
        return same[0]
    n = np.array(first.normalAt().toTuple())
    return max(faces, key=lambda f: abs(float(np.array(f.normalAt().toTuple()) @ n)))


def profile_tool(place: RoundPlace, scale: float) -> cq.Solid:
    """The region between c and l in l's plane, extruded along a straight edge or
    revolved around a circular rim: what a freeform bevel across an edge cuts away.

    Raises:
        OperationError: the set has more than one edge, the edge is neither straight nor
            a whole circle, or l and c bound no area.
    """
    if len(place.edges) > 1:
        raise OperationError(
            f"bevel: a freeform profile l follows one straight edge or one circular rim, "
            f"not {len(place.edges)} edges; a fillet radius or chamfer distances round a chain "
            "or an outline"
        )
    side, ctrl = place.side, place.profile
    c, edge = side.point, side.edge
    try:
        wire = cq.Wire.assembleEdges(
            [
                cq.Edge.makeLine(cq.Vector(*c), cq.Vector(*ctrl[0])),
                cq.Edge.makeBezier([cq.Vector(*p) for p in ctrl]),
                cq.Edge.makeLine(cq.Vector(*ctrl[3]), cq.Vector(*c)),
            ]
        )
        kind = edge.geomType()
        if kind == "LINE":
            start = np.array(edge.startPoint().toTuple())
            end = np.array(edge.endPoint().toTuple())
            along = side.tangent * float((end - start) @ side.tangent)
            back = side.tangent * float((start - c) @ side.tangent)
            tool = cq.Solid.extrudeLinear(wire.translate(cq.Vector(*back)), [], cq.Vector(*along))
        elif kind == "CIRCLE" and edge.IsClosed():
            center = edge.arcCenter()
            axis = cq.Vector(*np.cross(side.tangent, np.array(center.toTuple()) - c))
            tool = cq.Solid.revolve(wire, [], 360.0, center, center + axis)
        else:
            raise OperationError(
                "bevel: a freeform profile l follows a straight edge or a whole circular "
                f"rim; the edge at c {point_text(c)} is a {kind.lower()}"
            )
    except OperationError:
        raise
    except Exception as e:  # OCCT raises its own types for degenerate input
        raise OperationError(f"bevel: cannot build the region between c and l: {e}") from None
    if not tool.isValid() or abs(tool.Volume()) <= 1e-12 * scale**3:
        raise OperationError(
            "bevel: profile l and corner c bound no area (l self-intersects or is collinear with c)"
        )
    return tool
