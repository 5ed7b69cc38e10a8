# SPDX-License-Identifier: LGPL-2.1-or-later
"""The 3D sketch curves of an operation, labelled as the segmentation network learns them
(paper, "The Operators" and "Operator regression").

Labels (sketch/labels.py):
    extrude: edges of the moved face f (offset curve) 1, side edges (profile) 0;
    bevel: profile l on f 1, its offset l' = l + (c' - c) 0 (l drawn across an edge:
        l' at the edge's far end, or across the rim);
    add/sub and sweep: start curve 0, profile 1, end curve 2, where start and end are
        the two ends of the primitive ordered along n_f (for an addition the start is
        the base curve on f, for a subtraction the end is), which removes the
        add/subtract ambiguity (paper, Fig. "Handling ambiguity");
    shell: the inner rim on f (f's outline inset by t) 1; a line down an inner wall 0,
        drawn or not (the data generator's choice), so not part of the operation's own
        sketch.

Every curve is what a designer draws as one stroke: one straight edge, one profile
line, one whole circle, the whole bevel profile. Points are in mm, world frame.

On a curved f (a cylinder's or cone's side) a prism's or sweep's base curve is where
the primitive meets the surface (its outline on the tangent plane T carried along n_f
onto f), and its profile lines start there; an extrusion's offset curves move each
point of f's edges along the normal there.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import cadquery as cq
import numpy as np

from ..brep.faces import ResolvedFace, model_scale, resolve_face
from ..brep.geometry import bezier_points, plane_basis
from ..brep.protocol import (
    AddSubPrism,
    Bevel,
    Extrude,
    Mode,
    Operation,
    OperationError,
    OperatorType,
    Shell,
    Sweep,
    per_operator,
)
from ..brep.rounds import far_copy, nearest_edge
from .labels import (
    BEVEL_L,
    BEVEL_L_PRIME,
    END,
    EXTRUDE_OFFSET,
    EXTRUDE_PROFILE,
    PROFILE,
    SHELL_RIM,
    START,
)

CURVE_POINTS = 48  # samples of a curved edge, a Bezier or a circle
# Side edges are drawn from outline vertices where the outline turns by more than this;
# a tangent junction (a circle's seam, a fillet meeting its edge) has no edge to extend.
CORNER_DEG = 10.0


@dataclass(frozen=True)
class Curve:
    """One sketch curve.

    Attributes:
        points: (K, 3) polyline in mm (world frame); a straight edge has its two ends.
        label: the curve label C~ of its stroke pixels.
        closed: the polyline is a loop (a circle), its last point joins its first.
        relevant: part of the curve the view's occlusion test looks at (the offset curve
            for an extrusion, the base curve on f otherwise).
    """

    points: np.ndarray
    label: int
    closed: bool = False
    relevant: bool = False


def _edge_points(e: cq.Edge) -> np.ndarray:
    k = 2 if e.geomType() == "LINE" else CURVE_POINTS
    return np.array([e.positionAt(t).toTuple() for t in np.linspace(0, 1, k)])


def _segment(a, b) -> np.ndarray:
    return np.stack([np.asarray(a, float), np.asarray(b, float)])


def outline_corners(face: cq.Face) -> list[np.ndarray]:
    """The vertices of a face's outline (holes included) where it has a corner."""
    leaving: dict[tuple, list[np.ndarray]] = {}
    for e in face.Edges():
        for at, sign in ((0.0, 1.0), (1.0, -1.0)):  # tangents pointing away from the vertex
            p = np.array(e.positionAt(at).toTuple())
            t = sign * np.array(e.tangentAt(at).toTuple())
            leaving.setdefault(tuple(np.round(p, 6)), []).append(t / np.linalg.norm(t))
    limit = -np.cos(np.radians(CORNER_DEG))
    return [
        np.array(p) for p, ts in leaving.items() if len(ts) != 2 or float(ts[0] @ ts[1]) > limit
    ]


def extrude_curves(rf: ResolvedFace, op: Extrude, direction: np.ndarray) -> list[Curve]:
    def moved(points: np.ndarray) -> np.ndarray:
        if rf.surface is None:
            return points + rf.normal * op.d
        return points + rf.surface.normals(points) * op.d

    out = [Curve(moved(_edge_points(e)), EXTRUDE_OFFSET, relevant=True) for e in rf.face.Edges()]
    out += [
        Curve(np.stack([p, moved(p[None])[0]]), EXTRUDE_PROFILE) for p in outline_corners(rf.face)
    ]
    return out


def bevel_curves(rf: ResolvedFace, op: Bevel, direction: np.ndarray) -> list[Curve]:
    """l, and l' where the designer draws it again: at the crease's other end, or, for l
    drawn across an edge of f, at the edge's far end or across a rim (`far_copy`)."""
    l_curve = bezier_points(np.array(op.profile, float), CURVE_POINTS) + rf.offset
    if op.across:
        c = np.asarray(op.corner, float) + rf.offset
        edge, _ = nearest_edge(rf.face, c)
        return [
            Curve(l_curve, BEVEL_L, relevant=True),
            Curve(far_copy(edge, c, l_curve), BEVEL_L_PRIME),
        ]
    crease = np.subtract(op.opposite, op.corner)
    return [Curve(l_curve, BEVEL_L, relevant=True), Curve(l_curve + crease, BEVEL_L_PRIME)]


def _start_end(base, far, mode: Mode):
    """(start, end) ordered along n_f: a subtraction's far end lies below f."""
    return (far, base) if mode is Mode.SUBTRACT else (base, far)


def on_surface(rf: ResolvedFace, points: np.ndarray) -> np.ndarray:
    """Points (K, 3) of f's plane as they lie on f: themselves on a planar f; on a curved
    f, carried along n_f from the tangent plane onto the surface."""
    if rf.surface is None:
        return points
    t = rf.surface.crossings(points, rf.normal, model_scale(rf.face))
    if np.isnan(t).any():
        raise OperationError("the outline reaches past the side of the curved face")
    return points + t[:, None] * rf.normal


def prism_curves(rf: ResolvedFace, op: AddSubPrism, direction: np.ndarray) -> list[Curve]:
    base = np.array(op.polygon, float) + rf.offset
    far = base + rf.normal * op.d * op.mode.sign
    k = len(base)
    if rf.surface is None:
        sides = [_segment(base[i], base[(i + 1) % k]) for i in range(k)]
    else:  # each side where the prism meets the curved f
        sides = [
            on_surface(rf, np.linspace(base[i], base[(i + 1) % k], CURVE_POINTS)) for i in range(k)
        ]
    base_ends = np.array([side[0] for side in sides])
    far_sides = [_segment(far[i], far[(i + 1) % k]) for i in range(k)]
    out = []
    on_f = [(sides, True), (far_sides, False)]
    for (outline, relevant), label in zip(_start_end(*on_f, op.mode), (START, END), strict=True):
        out += [Curve(side, label, relevant=relevant) for side in outline]
    start, end = _start_end(base_ends, far, op.mode)
    out += [Curve(_segment(start[i], end[i]), PROFILE) for i in range(k)]
    return out


def silhouette_side(axis: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """The unit vector, perpendicular to the axis, that spans with it the plane through
    the axis facing the view (as square to the view direction as such a plane can be)."""
    side = np.cross(axis, direction)
    if np.linalg.norm(side) < 1e-6:  # looking along the axis: every such plane faces it
        return plane_basis(axis)[0]
    return side / np.linalg.norm(side)


def sweep_curves(rf: ResolvedFace, op: Sweep, direction: np.ndarray) -> list[Curve]:
    """Both circles and the two profile lines of the swept shape as seen along `direction`.

    The profile lines are c_p in the plane through the axis that faces the view, on both
    sides of the axis. For a cylinder they are exactly its silhouette; for a cone or a
    curved profile the true silhouette leaves that plane a little, but the profile in
    the plane is what the paper's sweep fitting reconstructs (a Bezier in the plane
    through the axis and the stroke's foot on c0), so the labels stay consistent with it.
    """
    c0 = np.array(op.center, float) + rf.offset
    axis = rf.normal * op.mode.sign
    c1 = c0 + axis * op.d
    side = silhouette_side(axis, np.asarray(direction, float))
    other = np.cross(axis, side)
    t = np.linspace(0, 2 * np.pi, 2 * CURVE_POINTS + 1)[:-1]
    ring = np.cos(t)[:, None] * side + np.sin(t)[:, None] * other
    base, far = on_surface(rf, c0 + op.r0 * ring), c1 + op.r1 * ring
    start, end = _start_end(base, far, op.mode)
    out = [
        Curve(start, START, closed=True, relevant=start is base),
        Curve(end, END, closed=True, relevant=end is base),
    ]
    rh = bezier_points(np.array(op.control_points(), float), CURVE_POINTS)
    for s in (1.0, -1.0):
        line = c0 + s * rh[:, :1] * side + rh[:, 1:2] * axis
        foot = on_surface(rf, line[:1])  # on a curved f, from where it meets f
        if not np.allclose(foot, line[:1]):
            line = np.vstack([foot, line[(line - foot) @ axis > 0]])
        out.append(Curve(line, PROFILE))
    return out


def rim_wires(face: cq.Face, t: float) -> list[cq.Wire]:
    """The inner rim a shell of thickness t leaves on its planar opened face: the face's
    outline inset by t (holes grown by t), as the offset walls meet f.

    Raises:
        OperationError: f is curved, or the inset leaves no rim (t too large for f).
    """
    if face.geomType() != "PLANE":
        raise OperationError("shell: the rim is drawn on a planar opened face f only")
    try:
        wires = face.outerWire().offset2D(-t, "arc")
        wires += [w for inner in face.innerWires() for w in inner.offset2D(t, "arc")]
    except Exception:  # OCCT's 2D offset fails when the inset vanishes
        wires = []
    if not wires:
        raise OperationError(f"shell: f's outline inset by t = {t:g} mm leaves no rim")
    return wires


def shell_curves(rf: ResolvedFace, op: Shell, direction: np.ndarray) -> list[Curve]:
    """The rim on f, one curve per edge of f's outline inset by t: a side of the rim is
    what a designer draws as one stroke (a loop is cut at its corners beforehand)."""
    return [
        Curve(_edge_points(e), SHELL_RIM, relevant=True)
        for w in rim_wires(rf.face, op.t)
        for e in w.Edges()
    ]


# The curves of each operator, from its resolved base face f, the operation and the view
# direction (world, into the scene; only a sweep's profile lines depend on it).
CURVES: dict[OperatorType, Callable[[ResolvedFace, Operation, np.ndarray], list[Curve]]] = (
    per_operator(
        {
            OperatorType.EXTRUDE: extrude_curves,
            OperatorType.BEVEL: bevel_curves,
            OperatorType.ADDSUB: prism_curves,
            OperatorType.SWEEP: sweep_curves,
            OperatorType.SHELL: shell_curves,
        },
        "sketch.curves.CURVES",
    )
)


def operation_curves(
    solid: cq.Shape, op: Operation, direction, face: ResolvedFace | None = None
) -> list[Curve]:
    """The labelled sketch curves of `op` applied to `solid` (its context).

    Args:
        solid: the context solid (before the operation).
        op: the operation.
        direction: the view direction (world, into the scene); only a sweep's profile
            lines depend on it.
        face: op.face resolved on `solid`, when the caller holds it already (then it is
            not resolved again).
    """
    return CURVES[op.type](face or resolve_face(solid, op.face), op, direction)
