# SPDX-License-Identifier: LGPL-2.1-or-later
"""The four operators of the paper and the shell as real B-rep operations through
cadquery/OCCT.

`apply_operation` is the one way in (`operation_result` beneath it also gives the
result's volume), and every operation takes the same path there: its parameters are
checked (`check_ranges`, `Operation.check`), its base face f is resolved once on the
current solid (or taken from a caller that holds it already: data generation), the
operator's builder (`TOOLS`) makes the primitive from that geometry, and `combine`
joins the primitive to the solid by the operation's Boolean (`Operation.boolean`), as
build123d's operations end in one combine by mode. The input solid is never modified.
Lengths are millimetres, points and vectors are in the world frame, and n_f is the
outward unit normal of f. A result is always one valid solid; anything else raises
`OperationError` with the reason.

On a curved f (a cylinder's or cone's side; beyond the paper) the extrusion offsets
the face along its normal (`extrude_tool`), and a prism or sweep stands on the tangent
plane T of f at the step's point p_f, along n_f there, reaching through T down to the
curved surface (`_stand_on_curved`). A bevel needs a planar f. A shell opens f, of any
kind, and offsets every other face inwards (`shell_tool`).
"""

from __future__ import annotations

import contextlib
import dataclasses
import itertools
from collections.abc import Callable
from dataclasses import dataclass

import cadquery as cq
import numpy as np
from OCP.BRepAlgoAPI import BRepAlgoAPI_Common, BRepAlgoAPI_Cut, BRepAlgoAPI_Fuse
from OCP.BRepOffsetAPI import BRepOffsetAPI_MakeThickSolid
from OCP.GeomAbs import GeomAbs_JoinType
from OCP.TopTools import TopTools_ListOfShape

from .apart import built_apart
from .corners import CREASE_COS, BevelCorner, bevel_corners, corner_along, corner_at
from .faces import (
    OperationError,
    ResolvedFace,
    base_face_index,
    face_at,
    model_box,
    model_scale,
    points_on_face,
    resolve_face,
)
from .geometry import bezier, crossing_sides, plane_basis, point_text, unit
from .protocol import (
    AddSubPrism,
    Bevel,
    Box,
    Extrude,
    Mode,
    Operation,
    OperatorType,
    Protocol,
    Shell,
    Sweep,
    WallTooThick,
    per_operator,
)
from .rounds import (
    RoundPlace,
    crease_side,
    edge_faces,
    edge_set,
    fillet_or_chamfer,
    profile_tool,
    round_place,
)

# Points farther than this (relative to the model diagonal) from f's plane are rejected.
PLANE_TOL = 1e-3
# How far past a curved f's surface (of the model's size) a prism or sweep standing on it
# starts: the primitive overlaps the solid there rather than leaving a sliver of gap.
REACH_MARGIN_REL = 1e-3


def make_box(box: Box) -> cq.Solid:
    """The base box of size (lx, ly, lz) mm, centred on the origin."""
    lx, ly, lz = box.size
    if min(box.size) <= 0:
        raise OperationError(f"box size must be positive, got {box.size}")
    return cq.Solid.makeBox(lx, ly, lz, cq.Vector(-lx / 2, -ly / 2, -lz / 2))


def _vec(p) -> cq.Vector:
    return cq.Vector(*[float(c) for c in p])


def on_face_plane(points, rf: ResolvedFace, scale: float, what: str) -> np.ndarray:
    """Points moved onto f's (possibly shifted) plane; far-off points are an error."""
    pts = np.asarray(points, dtype=float) + rf.offset
    plane_d = float(rf.normal @ rf.plane_point)
    dist = pts @ rf.normal - plane_d
    worst = int(np.argmax(np.abs(dist)))
    if abs(dist[worst]) > PLANE_TOL * scale:
        raise OperationError(f"{what}[{worst}] lies {dist[worst]:.4g} mm off the base face's plane")
    return pts - np.outer(dist, rf.normal)


@dataclass(frozen=True)
class OperationResult:
    """An operation's result: the solid, and its volume (mm^3), which the check that it
    is one solid computes anyway (callers need not compute it again)."""

    solid: cq.Solid
    volume: float


def combine(
    solid: cq.Shape, tool: cq.Shape, mode: Mode, what: str, check_valid: bool = True
) -> OperationResult:
    """The solid combined with an operation's primitive by `mode`: the one place every
    operation ends.

    Args:
        check_valid: whether OCCT's validity check runs on the result (`_single_solid`).
    Raises:
        OperationError: naming the step (`what`) when the result is not one valid solid.
    """
    result = tool if mode is Mode.REPLACE else boolean(solid, tool, mode)
    return _single_solid(result, what, solid, check_valid)


# OCCT's Boolean for each mode that has one.
BOOLEANS = {
    Mode.ADD: BRepAlgoAPI_Fuse,
    Mode.SUBTRACT: BRepAlgoAPI_Cut,
    Mode.INTERSECT: BRepAlgoAPI_Common,
}


def boolean(shape: cq.Shape, tool: cq.Shape, mode: Mode) -> cq.Shape:
    """`shape` fused with, cut by or intersected with `tool` (ADD, SUBTRACT, INTERSECT):
    cadquery's fuse, cut and intersect, with four OCCT options that leave the result the
    same (its BREP text, on each of 1,096 Booleans that data generation made, on planar
    and curved faces) and together save 5-11% of a Boolean's CPU."""
    algo = BOOLEANS[mode]()
    if isinstance(shape, cq.Compound):  # as cadquery: the compound's shapes stand for it,
        parts = list(shape)  # a fuse's first one alone as the argument
        inputs = (parts[:1], parts[1:] + [tool]) if mode is Mode.ADD else (parts, [tool])
    else:
        inputs = ([shape], [tool])
    args, tools = TopTools_ListOfShape(), TopTools_ListOfShape()
    for occt_list, shapes in zip((args, tools), inputs, strict=False):
        for s in shapes:
            occt_list.Append(s.wrapped)
    algo.SetArguments(args)
    algo.SetTools(tools)
    algo.SetRunParallel(False)  # threads cost CPU, and datagen's workers fill the cores
    algo.SetToFillHistory(False)  # no caller asks which input face became which
    algo.SetUseOBB(True)  # oriented boxes rule out more non-touching face pairs early
    algo.SetCheckInverted(False)  # the operators build no inside-out solid to look for
    algo.Build()
    return cq.Shape.cast(algo.Shape())  # raises, as cadquery's does, when OCCT failed


def _single_solid(
    shape: cq.Shape, what: str, before: cq.Shape, check_valid: bool = True
) -> OperationResult:
    """The one valid solid in a Boolean result, or an OperationError saying why not.
    Without `check_valid`, OCCT's validity check (BRepCheck) is left to the caller: it
    looks at the whole solid, and on a face with K holes its cost grows with K^2
    (`replay` checks its solids once, at the end)."""
    shape = shape.clean()
    solids = shape.Solids()
    if not solids:
        raise OperationError(f"{what}: the result is empty")
    if len(solids) > 1:
        raise OperationError(f"{what}: the result falls apart into {len(solids)} solids")
    solid = solids[0]
    if check_valid:
        _check_valid(solid, what)
    volume = solid.Volume()
    if volume <= 1e-9 * model_scale(before) ** 3:
        raise OperationError(f"{what}: the result has no volume")
    return OperationResult(solid, volume)


def _check_valid(solid: cq.Shape, what: str) -> None:
    """OperationError naming `what` when OCCT reports the solid as invalid."""
    if not solid.isValid():
        raise OperationError(f"{what}: OCCT reports the result as an invalid solid")


# ----------------------------------------------------------------- builders
# Each takes the current solid, the resolved base face f, the operation and the model's
# size (mm, for tolerances), and returns the primitive that `combine` joins to the solid.


def extrude_tool(solid: cq.Shape, rf: ResolvedFace, op: Extrude, scale: float) -> cq.Solid:
    """Face f swept by d along n_f: a pad (d > 0) or the pocket's volume (d < 0).

    On a curved f every point of f moves by d along the normal there (OCCT's offset of
    the face, thickened into a solid): a cylinder's radius grows by d when its outward
    normal points away from the axis (a boss's side), and a bore narrows by d (d > 0)
    or widens (d < 0); a cone's side moves parallel to itself. The region swept is
    bounded by f's own edges, so holes in f stay holes.
    """
    if rf.surface is None:
        return extrude_tool_planar(rf, op)
    surface = rf.surface
    inward = -op.d if surface.convex else op.d  # how far the surface moves to the axis
    if surface.slope == 0.0 and inward >= surface.radius:
        raise OperationError(
            f"extrude: d = {op.d:g} mm would take the cylinder's radius {surface.radius:g} "
            f"mm to {surface.radius - inward:g} mm; |d| must stay under the radius"
        )
    try:
        tool = rf.face.thicken(op.d)
    except Exception as e:  # OCCT's offset algorithm raises its own types
        raise OperationError(
            f"extrude: OCCT cannot offset the curved face f by {op.d:g} mm: {e}"
        ) from None
    if tool.isNull() or not tool.isValid() or tool.Volume() <= 1e-12 * scale**3:
        raise OperationError(
            f"extrude: offsetting the curved face f by {op.d:g} mm gives no valid solid"
        )
    return tool


def extrude_tool_planar(rf: ResolvedFace, op: Extrude) -> cq.Solid:
    """A planar f's outline (and its holes) extruded by d along n_f."""
    return cq.Solid.extrudeLinear(rf.face.outerWire(), rf.face.innerWires(), _vec(rf.normal * op.d))


@dataclass(frozen=True)
class BevelPlace:
    """Where a bevel is on the current solid: corner c, the crease c' - c and the profile
    l's control points (4, 3), world mm on f's plane."""

    corner: np.ndarray
    crease: np.ndarray
    profile: np.ndarray


def place_bevel(solid: cq.Shape, rf: ResolvedFace, op: Bevel, scale: float) -> BevelPlace:
    """The bevel's corner, crease and profile on the solid as it is now.

    c names a corner of f that a bevel can round (two straight edges of f meeting at c,
    convex, a straight edge of the solid, the crease, leaving c along -n_f), and l runs
    from one of those edges to the other. The crease runs along that edge to its far
    end, wherever that is now (c' is where it ended when the step was made). When an
    earlier step was edited, c itself may have moved (f grew or shrank): it is then
    found again as the nearest corner of f whose edges leave it the way l's ends lie
    from c and whose crease is as long as c -> c', and the bevel moves with it, l
    keeping its place relative to the corner's edges. A profile end past the far end of
    its edge is refused.

    Raises:
        OperationError: naming the field (corner c, the crease c -> c', profile l) that
            does not fit, and why.
    """
    if rf.surface is not None:
        raise OperationError(
            f"bevel: face f is the side of a {rf.surface.kind.value}; a "
            "bevel rounds a corner of a planar face"
        )
    (c,) = on_face_plane([op.corner], rf, scale, "bevel corner c")
    ctrl = on_face_plane(op.profile, rf, scale, "bevel profile l")
    crease = np.asarray(op.opposite, float) - np.asarray(op.corner, float)
    length = float(np.linalg.norm(crease))
    if length < 1e-6 * scale:
        raise OperationError("bevel: corner c and opposite corner c' coincide")
    if float(crease @ rf.normal) / length > -0.999:
        raise OperationError("bevel: the crease c -> c' must run into the solid along -n_f")
    if np.linalg.norm(ctrl[0] - c) < 1e-6 * scale or np.linalg.norm(ctrl[3] - c) < 1e-6 * scale:
        raise OperationError("bevel: profile l must start and end away from corner c")
    tol = 1e-6 * scale
    corners = bevel_corners(solid, rf.face, rf.normal, tol)
    here = corner_at(corners, c, tol)
    if here is not None:
        _check_profile_ends(c, ctrl, here, tol)
        found = here.opposite - here.c
        return BevelPlace(c, crease if np.linalg.norm(found - crease) <= tol else found, ctrl)
    if points_on_face(rf.face, c[None], tol, boundary=False)[0]:
        # an edit moves a corner off f (f shrank) or along f's outline (a side moved);
        # a point inside f was never one of its corners
        raise OperationError(
            f"bevel: corner c {point_text(c)} lies inside face f, not at a corner of it; c must be "
            "a vertex of f where two of its straight edges meet"
        )
    a, b = (unit(ctrl[k] - c) for k in (0, 3))
    moved = corner_along(corners, c, a, b, length, tol)
    if moved is None:
        raise OperationError(
            f"bevel: corner c {point_text(c)} is not a corner of face f that a bevel can "
            "round (two straight edges of f meeting there, with an edge of the solid running "
            "from it along -n_f), nor has such a corner moved from there (no corner of f has its "
            "edges along profile l's ends and a crease as long as c -> c')"
        )
    # l in the corner's (a, b) frame, laid on the corner found again
    coords = np.linalg.lstsq(np.stack([a, b], axis=1), (ctrl - c).T, rcond=None)[0].T
    moved_ctrl = moved.c + coords @ np.stack([moved.a, moved.b])
    _check_profile_ends(moved.c, moved_ctrl, moved, tol)
    return BevelPlace(moved.c, moved.opposite - moved.c, moved_ctrl)


def _check_profile_ends(c: np.ndarray, ctrl: np.ndarray, corner: BevelCorner, tol: float) -> None:
    """Refuse a profile whose ends do not lie on the corner's two edges of f."""
    for name, end in (("start l(0)", ctrl[0]), ("end l(1)", ctrl[3])):
        reach = float(np.linalg.norm(end - c))
        along = [
            (edge, edge_length)
            for edge, edge_length in ((corner.a, corner.la), (corner.b, corner.lb))
            if float(unit(end - c) @ edge) > CREASE_COS
        ]
        if not along:
            raise OperationError(
                f"bevel: the {name} of profile l {point_text(end)} is not on an edge "
                f"of f that meets at corner c {point_text(c)}"
            )
        if reach > along[0][1] + tol:
            raise OperationError(
                f"bevel: profile l ends {reach:.4g} mm from corner c {point_text(c)} along an edge "
                f"of f that is {along[0][1]:.4g} mm long: the bevel does not fit that corner "
                "(an earlier step made f smaller there?)"
            )


def bevel_tool(solid: cq.Shape, rf: ResolvedFace, op: Bevel, scale: float) -> cq.Solid:
    """The prism a bevel removes: the region between corner c and profile l on f,
    extruded along the crease c -> c' (`place_bevel` says where they are now)."""
    at = place_bevel(solid, rf, op, scale)
    c, ctrl = at.corner, at.profile
    _check_bevel_region(c, ctrl, rf.normal, scale)
    try:
        wire = cq.Wire.assembleEdges(
            [
                cq.Edge.makeLine(_vec(c), _vec(ctrl[0])),
                cq.Edge.makeBezier([_vec(p) for p in ctrl]),
                cq.Edge.makeLine(_vec(ctrl[3]), _vec(c)),
            ]
        )
        tool = cq.Solid.extrudeLinear(wire, [], _vec(at.crease))
    except Exception as e:  # OCCT raises its own types for degenerate input
        raise OperationError(f"bevel: cannot build the region between c and l: {e}") from None
    if not tool.isValid() or tool.Volume() <= 1e-12 * scale**3:
        raise OperationError(
            "bevel: profile l and corner c bound no area (l self-intersects or is collinear with c)"
        )
    return tool


def round_result(solid: cq.Solid, rf: ResolvedFace, op: Bevel, scale: float) -> OperationResult:
    """A bevel that `Bevel.is_round`: OCCT's fillet or chamfer on its edges (brep/rounds), or a
    freeform l cut along one straight edge or around one rim, and added instead where
    the edge is concave (l's region lies outside the solid).

    Raises:
        OperationError: naming the field that does not fit, or the OCCT failure.
    """
    place = place_round(solid, rf, op, scale)
    if op.regular:
        return _single_solid(fillet_or_chamfer(solid, op, place), op.name, solid)
    return combine(solid, profile_tool(place, scale), profile_mode(solid, place), op.name)


def place_round(solid: cq.Shape, rf: ResolvedFace, op: Bevel, scale: float) -> RoundPlace:
    """Where a bevel that `Bevel.is_round` is on the solid now: across an edge of f
    (brep/rounds.round_place), or along the crease that `place_bevel` finds.

    Raises:
        OperationError: naming the field that does not fit.
    """
    if op.across:
        return round_place(solid, rf, op, scale)
    at = place_bevel(solid, rf, op, scale)
    if not op.regular:
        _check_bevel_region(at.corner, at.profile, rf.normal, scale)
    side = crease_side(solid, at.corner, at.crease, unit(at.profile[0] - at.corner))
    edges = edge_set(solid, edge_faces(solid), side.first, side.edge, op.edges)
    return RoundPlace(side, at.profile, edges)


def profile_mode(solid: cq.Solid, place: RoundPlace) -> Mode:
    """SUBTRACT where l's region lies inside the solid (a convex edge), else ADD."""
    probe = (place.side.point + bezier(place.profile, np.array([0.5]))[0]) / 2
    return Mode.SUBTRACT if solid.isInside(cq.Vector(*probe)) else Mode.ADD


def locate_bevel(solid: cq.Shape, op: Bevel) -> Bevel:
    """The bevel as it lies on `solid` now: its corner, opposite corner and profile found
    again (`place_bevel`); the same bevel when nothing before it was edited.

    Raises:
        OperationError: f does not resolve, or the bevel no longer fits (the reason).
    """
    rf = resolve_face(solid, op.face, "bevel face f")
    if op.across:
        place = round_place(solid, rf, op, model_scale(solid))
        return dataclasses.replace(
            op,
            corner=_tuple(place.side.point),
            profile=tuple(_tuple(p) for p in place.profile),
        )
    at = place_bevel(solid, rf, op, model_scale(solid))
    return dataclasses.replace(
        op,
        corner=_tuple(at.corner),
        opposite=_tuple(at.corner + at.crease),
        profile=tuple(_tuple(p) for p in at.profile),
    )


def _tuple(p) -> tuple[float, float, float]:
    return tuple(float(x) for x in p)


def _check_bevel_region(c: np.ndarray, ctrl: np.ndarray, n: np.ndarray, scale: float) -> None:
    """Reject a profile l that leaves the wedge between the sides c -> l(0) and c -> l(1):
    the removed region would then cross itself (and OCCT returns nothing)."""
    u = ctrl[0] - c
    u /= np.linalg.norm(u)
    v = np.cross(n, u)

    def flat(p):
        return np.stack([(p - c) @ u, (p - c) @ v], axis=-1)

    a, b = flat(ctrl[0]), flat(ctrl[3])
    q = flat(bezier(ctrl, np.linspace(0, 1, 129)))[1:-1]
    s = np.sign(a[0] * b[1] - a[1] * b[0])
    if s == 0:
        raise OperationError("bevel: the ends of profile l are in line with corner c")
    in_a = s * (a[0] * q[:, 1] - a[1] * q[:, 0])  # >= 0 on c's side of line c-a
    in_b = s * (q[:, 0] * b[1] - q[:, 1] * b[0])
    if min(in_a.min(), in_b.min()) < -1e-6 * scale * scale:
        raise OperationError(
            "bevel: profile l leaves the corner's region (it crosses the "
            "face edges at c); keep it between the two edges"
        )


def prism_tool(solid: cq.Shape, rf: ResolvedFace, op: AddSubPrism, scale: float) -> cq.Solid:
    """The right prism of an add/subtract: polygon c on f extruded by d along n_f, or
    into the solid (-n_f) for SUBTRACT.

    On a curved f, c lies in the tangent plane T at p_f and d is measured along n_f
    from T (a boss's top is d above f at p_f, a slot's floor d below it); the prism
    reaches through T to the curved surface (`_stand_on_curved`)."""
    pts = on_face_plane(op.polygon, rf, scale, "prism polygon c")
    _check_simple_polygon(pts, rf.normal, scale)
    if rf.surface is None:
        wire = cq.Wire.makePolygon([_vec(p) for p in pts], close=True)
        return cq.Solid.extrudeLinear(wire, [], _vec(rf.normal * op.d * op.mode.sign))
    footprint = prism_footprint(pts)

    def prism(start: float, length: float) -> cq.Solid:
        wire = cq.Wire.makePolygon([_vec(p + rf.normal * start) for p in pts], close=True)
        return cq.Solid.extrudeLinear(wire, [], _vec(rf.normal * length))

    return _stand_on_curved(rf, op, footprint, prism, scale, "prism polygon c")


def prism_footprint(pts: np.ndarray) -> np.ndarray:
    """A prism's outline on T, sampled (16 points a side) for `curved_reach`."""
    closed = np.vstack([pts, pts[:1]])
    return np.concatenate(
        [
            a + (b - a) * np.linspace(0, 1, 16, endpoint=False)[:, None]
            for a, b in itertools.pairwise(closed)
        ]
    )


def sweep_footprint(center: np.ndarray, normal: np.ndarray, r0: float) -> np.ndarray:
    """A sweep's circle c0 on T, sampled (96 points) for `curved_reach`."""
    u, v = plane_basis(normal)
    angles = np.linspace(0, 2 * np.pi, 96, endpoint=False)
    return center + r0 * (np.outer(np.cos(angles), u) + np.outer(np.sin(angles), v))


@dataclass(frozen=True)
class Reach:
    """How a prism or sweep stands on a curved f: it starts `start` mm along n_f off the
    tangent plane T (below the surface for an ADD, above it for a SUBTRACT), and is
    trimmed to the solid that f's surface bounds (`inside`): what lies inside it is kept
    when `keep_inside`, else what lies outside."""

    start: float
    inside: cq.Solid
    keep_inside: bool
    extent: float  # how far `inside` reaches along the axis either side of p_f (mm)


def curved_reach(
    rf: ResolvedFace, op: AddSubPrism | Sweep, footprint: np.ndarray, scale: float, what: str
) -> Reach:
    """Where a prism's or sweep's primitive on a curved f starts, and what trims it.

    `footprint` (K, 3) samples the primitive's outline on the tangent plane T at p_f. An
    ADD runs from below the surface under the whole footprint up to d above T, and keeps
    what lies outside the material's side of f's surface; a SUBTRACT runs from above the
    surface down to d below T, and keeps what lies on the material's side. So a boss on a
    tube meets its wall all round, and a slot or hole cuts through the curved wall to
    depth d below p_f, not a sliver of it. For a cylinder, the footprint must lie within
    the cylinder's width.

    Raises:
        OperationError: for INTERSECT/REPLACE, or a footprint wider than the surface.
    """
    surface = rf.surface
    if op.mode not in (Mode.ADD, Mode.SUBTRACT):
        raise OperationError(
            f"{op.NOUN}: {op.mode.value} on a curved face f is not "
            "supported (add or subtract on it, or use a planar face)"
        )
    t = surface.crossings(footprint, rf.normal, scale)
    if np.isnan(t).any():
        k = int(np.argmax(np.isnan(t)))
        raise OperationError(
            f"{what} reaches past the side of the {surface.kind.value} "
            f"(at {point_text(footprint[k])} "
            f"the line along n_f misses it): keep it narrower than the {surface.kind.value}"
        )
    margin = REACH_MARGIN_REL * scale
    if op.mode is Mode.ADD:
        start = -(max(0.0, -float(t.min())) + margin)
    else:
        start = max(0.0, float(t.max())) + margin
    extent = 2.0 * (scale + op.d + float(np.abs(footprint - rf.plane_point).max()) + abs(start))
    return Reach(
        start,
        surface.solid(rf.plane_point, extent),
        (op.mode is Mode.ADD) != surface.convex,
        extent,
    )


def _stand_on_curved(
    rf: ResolvedFace,
    op: AddSubPrism | Sweep,
    footprint: np.ndarray,
    primitive: Callable[[float, float], cq.Solid],
    scale: float,
    what: str,
) -> cq.Solid:
    """A prism's or sweep's primitive on a curved f, meeting f without gap or overlap
    (`curved_reach`): `primitive(start, length)` is the primitive from `start` mm along
    n_f off T, `length` mm along n_f (negative: against it).

    Raises:
        OperationError: as `curved_reach`, or the trimmed primitive is not one solid.
    """
    reach = curved_reach(rf, op, footprint, scale, what)
    length = op.d - reach.start if op.mode is Mode.ADD else -op.d - reach.start
    tool = primitive(reach.start, length)
    clipped = boolean(tool, reach.inside, Mode.INTERSECT if reach.keep_inside else Mode.SUBTRACT)
    solids = clipped.Solids()
    if len(solids) != 1 or not solids[0].isValid():
        raise OperationError(
            f"{op.NOUN}: the primitive does not meet the curved face f in one piece"
        )
    return solids[0]


def _check_simple_polygon(pts: np.ndarray, n: np.ndarray, scale: float) -> None:
    """Reject polygons with repeated vertices, no area, or crossing sides."""
    u, v = plane_basis(n)
    q = np.stack([pts @ u, pts @ v], axis=1)
    k = len(q)
    for i in range(k):
        if np.linalg.norm(q[i] - q[(i + 1) % k]) < 1e-6 * scale:
            raise OperationError(f"prism: polygon vertices {i} and {(i + 1) % k} coincide")
    crossing = crossing_sides(q)
    if crossing:
        raise OperationError(
            f"prism: polygon sides {crossing[0]} and {crossing[1]} cross each other"
        )
    area = 0.5 * abs(
        sum(q[i, 0] * q[(i + 1) % k, 1] - q[(i + 1) % k, 0] * q[i, 1] for i in range(k))
    )
    if area < 1e-8 * scale**2:
        raise OperationError("prism: base polygon c has no area")


def sweep_tool(solid: cq.Shape, rf: ResolvedFace, op: Sweep, scale: float) -> cq.Solid:
    """The solid of revolution of profile c_p about the axis through c0 and c1 (c0's
    centre on f, the axis along n_f, or into the solid for SUBTRACT).

    A straight c_p gives an analytic cylinder (r0 == r1) or cone, exact in STEP and
    fast in Booleans; otherwise c_p is revolved. On a curved f, c0 lies on the tangent
    plane T at p_f and d is measured from T (a radial peg d tall above f at p_f, a
    drilled hole d deep below it); a cylinder of c0 carries it through T to the surface
    (`_stand_on_curved`).
    """
    (center,) = on_face_plane([op.center], rf, scale, "sweep centre of c0")
    if rf.surface is not None:
        footprint = sweep_footprint(center, rf.normal, op.r0)  # c0 on T

        def primitive(start: float, length: float) -> cq.Solid:
            # the sweep itself, and a cylinder of c0 through T to the surface
            down = cq.Solid.makeCylinder(
                op.r0,
                abs(start),
                _vec(center + rf.normal * start),
                _vec(-rf.normal * np.sign(start)),
            )
            swept = sweep_primitive(center, op, rf.normal * op.mode.sign)
            return _single_solid(
                boolean(swept, down, Mode.ADD), f"{op.NOUN} on a curved face", down
            ).solid

        return _stand_on_curved(rf, op, footprint, primitive, scale, "sweep circle c0")
    return sweep_primitive(center, op, rf.normal * op.mode.sign)


def sweep_primitive(center: np.ndarray, op: Sweep, axis: np.ndarray) -> cq.Solid:
    """The swept solid itself: c_p revolved about the axis (unit) from c0's `center`."""
    ctrl = np.array(op.control_points(), dtype=float)
    chord = ctrl[0] + (ctrl[3] - ctrl[0]) * np.array([[1 / 3], [2 / 3]])
    if np.allclose(ctrl[1:3], chord, rtol=0, atol=1e-9 * max(op.d, op.r0, op.r1)):
        if abs(op.r0 - op.r1) <= 1e-12 * max(op.r0, op.r1):
            return cq.Solid.makeCylinder(op.r0, op.d, _vec(center), _vec(axis))
        return cq.Solid.makeCone(op.r0, op.r1, op.d, _vec(center), _vec(axis))
    radial, _ = plane_basis(axis)  # any direction square to the axis, for a full turn

    def world(rh):
        return _vec(center + radial * rh[0] + axis * rh[1])

    top = center + axis * op.d
    wire = cq.Wire.assembleEdges(
        [
            cq.Edge.makeLine(_vec(center), world(ctrl[0])),
            cq.Edge.makeBezier([world(p) for p in ctrl]),
            cq.Edge.makeLine(world(ctrl[3]), _vec(top)),
            cq.Edge.makeLine(_vec(top), _vec(center)),
        ]
    )
    tool = cq.Solid.revolve(wire, [], 360.0, _vec(center), _vec(top))
    if not tool.isValid():
        raise OperationError("sweep: the swept primitive is not a valid solid")
    return tool


# OCCT's tolerance for the thick solid's offset faces (mm), PartDesign Thickness's own, so
# that the conversion builds the same solid (docs/measurements.md, operators.THICK_TOL).
THICK_TOL = 1e-3
# OCCT's offset takes well under a second on the models sketched here (0.02 s on a box);
# one that runs longer than this is looping and is refused (docs/measurements.md,
# operators.THICK_TIMEOUT_S).
THICK_TIMEOUT_S = 20.0
# The surfaces whose inward offset the shell builds: OCCT offsets these exactly. Its
# offset of a bevel's extruded profile or of a sweep's revolved Bezier profile is an
# approximation whose result crashed OCCT's own validity check on a sampled model
# (docs/protocol.md), so a solid with such a face is refused before OCCT is asked.
OFFSET_SURFACES = ("PLANE", "CYLINDER", "CONE", "SPHERE", "TORUS")
# A wall may come out this much (relative to t) thinner than t before the shell is refused
# as self-intersecting: OCCT's offset is exact on planes, cylinders and cones
# (docs/measurements.md, operators.WALL_TOL_REL).
WALL_TOL_REL = 1e-3


def shell_tool(solid: cq.Shape, rf: ResolvedFace, op: Shell, scale: float) -> cq.Solid:
    """The solid hollowed out, open at f, every other face offset inwards by t (OCCT's
    thick solid, offset faces joined by intersection, as PartDesign Thickness's Join
    "Intersection" builds it: with arcs, OCCT crashed on a sampled model of a cone and
    a slanted plane).
    Every face must lie on one of OFFSET_SURFACES.

    OCCT does not refuse every offset it cannot build: past half the solid's thickness it
    returns the solid unchanged, and where offset faces cross it may return walls that
    cut through the outside. The result is therefore checked: it holds a cavity, and the
    cavity keeps at least t (less `WALL_TOL_REL`) from every face but f.

    Raises:
        OperationError: naming t and why it cannot be built (WallTooThick where the
            offset was built but t is more than the solid takes).
    """
    what = f"shell: wall thickness t = {op.t:g} mm cannot be built"
    freeform = sorted(
        {f.geomType().lower() for f in solid.Faces() if f.geomType() not in OFFSET_SURFACES}
    )
    if freeform:
        raise OperationError(
            f"shell: the walls cannot follow the solid's {' and '.join(freeform)} faces (a "
            "bevel's or a curved sweep's profile); OCCT offsets planes, cylinders, cones, "
            "spheres and tori only"
        )
    thick = _thick_solid(solid, rf.face, op.t)
    if thick is None:
        raise OperationError(
            f"{what}: OCCT's offset of the walls fails on this solid (offset faces that "
            "cross, or a face it cannot offset); a smaller t may build"
        )
    solids = thick.Solids()
    if len(solids) != 1:
        raise OperationError(f"{what}: OCCT's offset is not one valid solid; a smaller t may build")
    cavity = boolean(solid, solids[0], Mode.SUBTRACT).Solids()
    if not cavity or sum(c.Volume() for c in cavity) <= 1e-9 * scale**3:
        raise WallTooThick(
            f"{what}: it is more than the solid allows (walls t thick from every face "
            "leave no cavity)"
        )
    walls = [f for f in solid.Faces() if not f.isSame(rf.face)]
    inner = cq.Compound.makeCompound(cavity)
    thinnest = min(inner.distance(f) for f in walls)
    if thinnest < op.t * (1 - WALL_TOL_REL):
        raise WallTooThick(
            f"{what}: the offset walls cross (a wall comes out {thinnest:.3g} mm thin); a "
            "smaller t may build"
        )
    return solids[0]


def _thick_solid(solid: cq.Shape, face: cq.Face, t: float) -> cq.Shape | None:
    """OCCT's thick solid of `solid` open at `face`, walls t thick (`shell_tool`'s
    settings), checked valid; None where OCCT fails, reports an invalid solid, crashes or
    runs past THICK_TIMEOUT_S.

    OCCT's offset crashes the process on some solids and loops for ever on others
    (sampled models of planes and cones), so it is built apart (`apart.built_apart`).
    """

    def build() -> cq.Shape | None:
        opened = TopTools_ListOfShape()
        opened.Append(face.wrapped)
        builder = BRepOffsetAPI_MakeThickSolid()
        builder.MakeThickSolidByJoin(
            solid.wrapped,
            opened,
            -t,
            THICK_TOL,
            Intersection=False,
            Join=GeomAbs_JoinType.GeomAbs_Intersection,
        )
        try:
            builder.Build()
        except Exception:  # OCCT raises as well as reports "not done"
            return None
        if not builder.IsDone():
            return None
        thick = cq.Shape.cast(builder.Shape())
        return thick if thick.isValid() else None

    return built_apart(build, THICK_TIMEOUT_S)


# The builder of each operator's primitive.
TOOLS: dict[OperatorType, Callable[[cq.Shape, ResolvedFace, Operation, float], cq.Solid]] = (
    per_operator(
        {
            OperatorType.EXTRUDE: extrude_tool,
            OperatorType.BEVEL: bevel_tool,
            OperatorType.ADDSUB: prism_tool,
            OperatorType.SWEEP: sweep_tool,
            OperatorType.SHELL: shell_tool,
        },
        "operators.TOOLS",
    )
)


# Lengths and points an operation may hold, relative to the model's size (its bounding
# box diagonal): OCCT's own failures outside this range say nothing a user can act on.
MIN_LENGTH_REL, MAX_EXTENT_REL = 1e-6, 100.0
LENGTHS = ("d", "r0", "r1", "t")


def check_ranges(solid: cq.Shape, op: Operation) -> None:
    """Refuse parameters no operator builds, in the user's terms, before OCCT sees them.

    Raises:
        OperationError: naming the parameter, its value and the range for this model.
    """
    lo, hi = model_box(solid)
    scale, center = float(np.linalg.norm(hi - lo)), (lo + hi) / 2
    for f in dataclasses.fields(op):
        value = getattr(op, f.name)
        if f.name in LENGTHS:
            lo, hi = MIN_LENGTH_REL * scale, MAX_EXTENT_REL * scale
            if not lo <= abs(value) <= hi:
                raise OperationError(
                    f"{op.type.value}: {f.name} = {value:g} mm is out of range for this model "
                    f"(size {scale:.4g} mm): |{f.name}| must be from {lo:.3g} to {hi:.3g} mm"
                )
        elif f.name != "face" and isinstance(value, tuple):
            pts = np.asarray(value, float)
            pts = pts.reshape(-1, pts.shape[-1])
            # 3D points from the model's centre; a sweep's (r, h) profile as they are
            far = float(np.abs(pts - center if pts.shape[1] == 3 else pts).max())
            if far > MAX_EXTENT_REL * scale:
                raise OperationError(
                    f"{op.type.value}: {f.name} lies {far:.4g} mm from the model (size "
                    f"{scale:.4g} mm); at most {MAX_EXTENT_REL * scale:.4g} mm"
                )


def apply_operation(solid: cq.Solid, op: Operation, face: cq.Face | None = None) -> cq.Solid:
    """Apply one protocol operation to `solid`.

    The parameters are checked, f is resolved on the solid (following it when an earlier
    step moved it), the operator's primitive is built there (`TOOLS`) and combined with
    the solid by the operation's Boolean. `solid` is not changed (the work is done on a
    copy: OCCT adds p-curves to what it cuts).

    Args:
        face: the planar face of `solid` that op.face designates, when the caller holds
            it already (data generation draws op.face from it): it is not resolved
            again. The caller vouches for it: a face op.face does not resolve to gives
            another operation.
    Raises:
        OperationError: a parameter is out of range, f does not resolve, the geometry is
            off f or degenerate, or the result is not one valid solid; the message says
            which.
        ValueError: `face` is not a face of `solid`, or op.face is curved.
    """
    return operation_result(solid, op, face).solid


def operation_result(
    solid: cq.Solid, op: Operation, face: cq.Face | None = None, check_valid: bool = True
) -> OperationResult:
    """`apply_operation`'s result with its volume (the same arguments and errors).

    Args:
        check_valid: False leaves OCCT's validity check of the result to the caller
            (`replay` checks once, at the end).
    """
    check_ranges(solid, op)
    index = None if face is None else _held_face_index(solid, face, op)
    try:
        op.check()
        solid = solid.copy()
        # BRepBuilderAPI_Copy keeps the order of the faces: the held face is the copy's
        # face at the same index
        rf = (
            resolve_face(solid, op.face, f"{op.NOUN} face f")
            if index is None
            else ResolvedFace.of(face_at(solid, index))
        )
        if op.type is OperatorType.BEVEL and op.is_round:
            return round_result(solid, rf, op, model_scale(solid))
        tool = TOOLS[op.type](solid, rf, op, model_scale(solid))
        return combine(solid, tool, op.boolean, op.name, check_valid)
    except OperationError:
        raise
    except Exception as e:  # an OCCT failure deep in a Boolean is still a user-level error
        raise OperationError(f"{op.type.value}: OCCT failed to build the result: {e}") from None


def _held_face_index(solid: cq.Shape, face: cq.Face, op: Operation) -> int:
    """The index in solid.Faces() of the base face a caller holds (ValueError: it is not
    the solid's, or op.face is curved: `ResolvedFace.of` knows planar faces only)."""
    if op.face.surface.curved:
        raise ValueError(f"{op.NOUN}: a held base face must be planar; op.face is curved")
    return base_face_index(solid, face)


def replay(protocol: Protocol, on_step: Callable[[int], None] | None = None) -> list[cq.Solid]:
    """The solid after the base box and after each operation, in order.

    OCCT's validity check runs on the final solid, and on the solid before a step that
    replaces it (REPLACE), not after every step: on a face with K holes it costs K^2,
    which made a long replay grow with the cube of its steps. Where that check or a
    step fails, the protocol is built again with every check after every step, so the
    error names the first step that does not build, as a step-by-step check would.

    Args:
        on_step: called with each step's number (1-based) once it is built (progress).
    Raises:
        OperationError: naming the step (1-based) that could not be built.
    """
    return _replay(protocol, on_step, keep=True)


def build(protocol: Protocol, on_step: Callable[[int], None] | None = None) -> cq.Solid:
    """The final solid of a protocol (on_step, checks and errors: as for `replay`),
    holding only the solid of the step being built (`replay` holds every step's)."""
    return _replay(protocol, on_step, keep=False)[-1]


def _replay(
    protocol: Protocol, on_step: Callable[[int], None] | None, keep: bool
) -> list[cq.Solid]:
    """`replay` (`keep`: every step's solid) or `build` (the last one only)."""
    try:
        return _steps(protocol, on_step, keep, check_each=False)
    except OperationError:
        # some step fails, or an unchecked one left an invalid solid: the first step
        # that fails its checks is the one to name
        return _steps(protocol, None, keep, check_each=True)


def _steps(
    protocol: Protocol, on_step: Callable[[int], None] | None, keep: bool, check_each: bool
) -> list[cq.Solid]:
    """The protocol's solids (`_replay`), OCCT's validity checked after each step
    (`check_each`) or only where an unchecked solid would be lost: before a step that
    replaces it, and at the end.

    Raises:
        OperationError: naming the step that failed (without `check_each`, perhaps a
            later one than the first that does not build).
    """
    solids = [make_box(protocol.base)]
    for i, op in enumerate(protocol.operations, 1):
        if not check_each and op.boolean is Mode.REPLACE:
            _check_valid(solids[-1], f"step {i - 1}")
        solid = _step(solids[-1], op, i, check_each)
        if keep:
            solids.append(solid)
        else:
            solids[-1] = solid
        if on_step:
            on_step(i)
    if not check_each:
        _check_valid(solids[-1], f"step {len(protocol.operations)}")
    return solids


def _step(solid: cq.Solid, op: Operation, i: int, check_valid: bool) -> cq.Solid:
    """Step i of a replay (OperationError: naming the step)."""
    try:
        return operation_result(solid, op, check_valid=check_valid).solid
    except OperationError as e:
        raise OperationError(f"step {i} ({op.type.value}): {e}") from None


def apply_what_builds(solid: cq.Shape, operations: list[Operation]) -> cq.Shape:
    """`solid` with the operations applied in turn, each on the solid the ones before
    built (its face followed where an earlier one moved it); one that no longer builds
    there (its face gone) is left out. For measuring where a protocol with some steps
    changed ends, not for building one: `replay` names a step that fails."""
    for op in operations:
        with contextlib.suppress(OperationError):
            solid = apply_operation(solid, op)
    return solid
