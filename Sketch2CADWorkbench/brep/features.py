# SPDX-License-Identifier: LGPL-2.1-or-later
"""Each step of a protocol as the feature a parametric CAD user would build for it.

A feature is the base box, a planar face of the solid before padded or pocketed, the
solid before hollowed open at a face (a shell: PartDesign's Thickness), or a closed
outline on a sketch plane (lines and cubic Beziers through named points) padded,
pocketed, revolved or grooved. Every coordinate of the outline is 0 or a named
dimension (`Outline.dims`): the step's parameters (d, r0, r1, the profile's control
points, polygon c's vertices in f's plane), so that a sketch holding it can be fully
constrained by them. The PartDesign conversion (freecad_layer/partdesign) and the script
export (brep/script) both read these plans; the geometry is the core's own, taken where
the core's replay put each step (`plan_protocol`).

What a feature cannot say is kept beside it: on a curved face the operators trim a
prism or sweep to the face's surface (`Clip`); a feature that ignores the trim is the
operator's solid only where the solid fills the surface's other side, which the
conversion checks against the core's solid.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from enum import Enum

import cadquery as cq
import numpy as np
from OCP.BRepAdaptor import BRepAdaptor_Surface

from .faces import (
    NORMAL_COS_TOL,
    CurvedSurface,
    FaceRef,
    OperationError,
    interior_point,
    model_scale,
    resolve_face,
)
from .geometry import plane_basis, unit
from .operators import (
    curved_reach,
    make_box,
    on_face_plane,
    place_bevel,
    place_round,
    prism_footprint,
    profile_mode,
    replay,
    shell_tool,
    sweep_footprint,
)
from .protocol import AddSubPrism, Bevel, Box, Extrude, Mode, Operation, Protocol, Shell, Sweep
from .rounds import edge_faces, edges_at, face_on_side, fillet_or_chamfer_edges

Vec2 = tuple[float, float]
Vec3 = tuple[float, float, float]
# A coordinate within this share of the model's size of 0 (or of another) is that value.
SAME_REL = 1e-9


class Kind(Enum):
    """How a feature makes its solid."""

    BOX = "box"  # the base box
    FACE = "face"  # a planar face of the solid before, extruded along its normal
    EXTRUDE = "extrude"  # an outline on a sketch plane, extruded
    REVOLVE = "revolve"  # an outline on a sketch plane, revolved about the sketch's v axis
    THICKNESS = "thickness"  # the solid before, open at a face, hollowed to walls `length` thick
    FILLET = "fillet"  # edges of the solid before rounded with a constant radius
    CHAMFER = "chamfer"  # edges of the solid before chamfered by two distances


@dataclass(frozen=True)
class Frame:
    """A sketch plane: its origin, its u axis and its normal (world, unit); v = n x u."""

    origin: Vec3
    u: Vec3
    normal: Vec3

    @property
    def v(self) -> Vec3:
        return _tup(np.cross(self.normal, self.u))

    def to_3d(self, q: Vec2) -> np.ndarray:
        return np.asarray(self.origin) + q[0] * np.asarray(self.u) + q[1] * np.asarray(self.v)


@dataclass(frozen=True)
class Point:
    """A point of an outline: its name, and each coordinate's dimension name (None: the
    coordinate is 0) and value (mm)."""

    name: str
    dims: tuple[str | None, str | None]
    at: Vec2


@dataclass(frozen=True)
class Outline:
    """A closed outline: points (in the order their dimensions matter most), and its
    segments in order around it, each a line (2 point names) or a cubic Bezier (4: its
    ends and inner control points). A dimension name used by two points is one value;
    the points then lie on one line of the outline, across or along the sketch's axes."""

    points: tuple[Point, ...]
    segments: tuple[tuple[str, ...], ...]

    def point(self, name: str) -> Point:
        return next(p for p in self.points if p.name == name)

    @property
    def dims(self) -> dict[str, float]:
        """Each named dimension and its value (mm)."""
        out: dict[str, float] = {}
        for p in self.points:
            for name, value in zip(p.dims, p.at, strict=False):
                if name is not None:
                    out.setdefault(name, value)
        return out


@dataclass(frozen=True)
class Clip:
    """The solid bounded by a curved f's surface that trims a primitive standing on it
    (brep/operators.curved_reach): a cylinder (r_base == r_far) or cone from `base`
    along `axis`, `length` long; `keep_inside` keeps what lies in it, else what lies out."""

    kind: str  # "cylinder" or "cone"
    base: Vec3
    axis: Vec3
    r_base: float
    r_far: float
    length: float
    keep_inside: bool


@dataclass(frozen=True)
class Feature:
    """A step as a feature (module docstring).

    `mode` says how its solid combines with the solid before. EXTRUDE: the outline goes
    `length` mm along `direction` (the sketch normal for an ADD, its opposite for a
    SUBTRACT, unless given) and `back` mm the other way; `length` and `back` are
    measured along the sketch normal. REVOLVE: the outline turns `angle` degrees about
    the sketch's v axis (right-handed). FACE: `face` (on the solid before) moves `length`
    mm along its outward normal (ADD) or into the solid (SUBTRACT). THICKNESS: the solid
    before, open at `face`, every other face moved `length` mm inwards (the cavity is
    what it removes: SUBTRACT). BOX: `size`, centred on the origin. FILLET and CHAMFER:
    the edges of the solid before through `edges` (a point on each), rounded by
    dims["radius"] or chamfered by dims["d1"] on the face through the edge's `sides`
    point (its outward normal there beside it) and dims["d2"] on the other. `dims` adds
    named values that are not sketch coordinates.
    """

    step: int
    kind: Kind
    mode: Mode
    frame: Frame | None = None
    outline: Outline | None = None
    length: float = 0.0
    back: float = 0.0
    direction: Vec3 | None = None
    angle: float = 360.0
    face: FaceRef | None = None
    size: Vec3 | None = None
    clip: Clip | None = None
    dims: dict[str, float] = field(default_factory=dict)
    edges: tuple[Vec3, ...] = ()
    sides: tuple[tuple[Vec3, Vec3], ...] = ()


@dataclass(frozen=True)
class Plan:
    """A protocol's features, and the core's solid after each step (solids[0]: the box)."""

    protocol: Protocol
    features: list[Feature]
    solids: list[cq.Solid]


def plan_protocol(protocol: Protocol) -> Plan:
    """The feature of each step of a protocol, where the core's replay puts it.

    Raises:
        OperationError: naming the step that does not build (as `replay`).
    """
    solids = replay(protocol)
    features = [Feature(0, Kind.BOX, Mode.ADD, size=protocol.base.size)]
    for i, op in enumerate(protocol.operations, 1):
        try:
            features.append(plan_step(solids[i - 1], op, i))
        except OperationError as e:
            raise OperationError(f"step {i} ({op.type.value}): {e}") from None
    return Plan(protocol, features, solids)


def plan_step(solid: cq.Shape, op: Operation, step: int) -> Feature:
    """The feature of one operation on the solid before it (its base face resolved there;
    `Feature.face` is the face reference moved onto it)."""
    rf = resolve_face(solid, op.face, f"{op.NOUN} face f")
    scale = model_scale(solid)
    if isinstance(op, Extrude):
        feature = _extrude(rf, op, step, scale)
    elif isinstance(op, Bevel):
        feature = _bevel(solid, rf, op, step, scale)
    elif isinstance(op, AddSubPrism):
        feature = _prism(rf, op, step, scale)
    elif isinstance(op, Shell):
        feature = Feature(step, Kind.THICKNESS, Mode.SUBTRACT, length=op.t, dims={"t": op.t})
    else:
        feature = _sweep(rf, op, step, scale)
    point = np.asarray(op.face.point, float) + rf.offset
    return dataclasses.replace(feature, face=FaceRef(_tup(point), op.face.normal, op.face.surface))


def _extrude(rf, op: Extrude, step: int, scale: float) -> Feature:
    mode = Mode.ADD if op.d > 0 else Mode.SUBTRACT
    if rf.surface is None:
        return Feature(step, Kind.FACE, mode, length=abs(op.d), dims={"d": op.d})
    # a cylinder's or cone's side moved along its normals: the band between the side and
    # its offset, revolved over the side's angular span
    surface: CurvedSurface = rf.surface
    position = _surface_position(rf.face)
    x_dir, y_dir = (np.array(d.Coord()) for d in (position.XDirection(), position.YDirection()))
    u0, u1, _, _ = rf.face.uvBounds()
    direct = float(np.cross(surface.axis, x_dir) @ y_dir) > 0  # u turns right-handed about axis
    start = u0 if direct else u1
    radial = math.cos(start) * x_dir + math.sin(start) * y_dir
    heights = [
        float((np.array(v.toTuple()) - surface.origin) @ surface.axis)
        for edge in rf.face.Edges()
        for v in (edge.startPoint(), edge.endPoint(), edge.positionAt(0.5))
    ]
    h0, h1 = min(heights), max(heights)
    n_rh = np.array([1.0, -surface.slope]) / math.hypot(1.0, surface.slope)
    n_rh = n_rh if surface.convex else -n_rh
    p0 = np.array([surface.radius + surface.slope * h0, h0])
    p1 = np.array([surface.radius + surface.slope * h1, h1])
    q0, q1 = p0 + op.d * n_rh, p1 + op.d * n_rh
    if surface.slope == 0.0:
        names = (
            ("radius", "h0"),
            ("radius", "h1"),
            ("offset_radius", "h1"),
            ("offset_radius", "h0"),
        )
    else:
        names = tuple((f"{k}_r", f"{k}_h") for k in ("p0", "p1", "q1", "q0"))
    pts = tuple(
        _point(k, names[i], q, scale)
        for i, (k, q) in enumerate(zip(("p0", "p1", "q1", "q0"), (p0, p1, q1, q0), strict=False))
    )
    outline = Outline(pts, (("p0", "p1"), ("p1", "q1"), ("q1", "q0"), ("q0", "p0")))
    frame = Frame(_tup(surface.origin), _tup(radial), _tup(np.cross(radial, surface.axis)))
    angle = math.degrees(u1 - u0)
    return Feature(
        step,
        Kind.REVOLVE,
        mode,
        frame,
        outline,
        angle=min(angle, 360.0),
        dims={"d": op.d},
    )


def _surface_position(face: cq.Face):
    adaptor = BRepAdaptor_Surface(face.wrapped)
    g = adaptor.Cylinder() if face.geomType() == "CYLINDER" else adaptor.Cone()
    return g.Position()


def _bevel(solid, rf, op: Bevel, step: int, scale: float) -> Feature:
    if op.is_round:
        return _round(solid, rf, op, step, scale)
    at = place_bevel(solid, rf, op, scale)
    c, ctrl, n = at.corner, at.profile, rf.normal
    u = unit(ctrl[0] - c)
    frame = Frame(_tup(c), _tup(u), _tup(n))
    flat = _flat(frame, ctrl)
    names = ("l_start", "l_control1", "l_control2", "l_end")
    pts = (Point("c", (None, None), (0.0, 0.0)),) + tuple(
        _point(k, (f"{k}_u", f"{k}_v"), q, scale) for k, q in zip(names, flat, strict=False)
    )
    outline = Outline(pts, (("c", "l_start"), names, ("l_end", "c")))
    depth = -float(at.crease @ n)
    crease = unit(at.crease)
    tilted = float(np.linalg.norm(crease + n)) > SAME_REL
    return Feature(
        step,
        Kind.EXTRUDE,
        Mode.SUBTRACT,
        frame,
        outline,
        length=depth,
        direction=_tup(crease) if tilted else None,
        dims={"crease": depth},
    )


def _round(solid, rf, op: Bevel, step: int, scale: float) -> Feature:
    """A fillet or chamfer on the bevel's edges, or its freeform l across one edge:
    padded or pocketed along a straight edge, revolved or grooved around a rim."""
    place = place_round(solid, rf, op, scale)
    points = tuple(_tup(e.positionAt(0.5).toTuple()) for e in place.edges)
    if op.radius is not None:
        return Feature(step, Kind.FILLET, Mode.SUBTRACT, edges=points, dims={"radius": op.radius})
    if op.distances is not None:
        faces_map = edge_faces(solid)
        sides = []
        for e in place.edges:
            face = face_on_side(faces_map, e, place.side.first)
            at = interior_point(face) if face.geomType() == "PLANE" else face.positionAt(0.5, 0.5)
            normal = face.normalAt(cq.Vector(*at)).toTuple()
            sides.append((_tup(at), _tup(normal)))
        d1, d2 = op.distances
        return Feature(
            step,
            Kind.CHAMFER,
            Mode.SUBTRACT,
            edges=points,
            sides=tuple(sides),
            dims={"d1": d1, "d2": d2},
        )
    mode = profile_mode(solid, place)
    c, t, edge = place.side.point, place.side.tangent, place.side.edge
    if edge.geomType() == "LINE":
        start = np.array(edge.startPoint().toTuple())
        end = np.array(edge.endPoint().toTuple())
        normal = t if mode is Mode.ADD else -t  # either way the outline goes along +t
        origin = c + t * float((start - c) @ t)
        frame = Frame(_tup(origin), _tup(unit(place.profile[0] - c)), _tup(normal))
        kind, length = Kind.EXTRUDE, abs(float((end - start) @ t))
    else:
        center = np.array(edge.arcCenter().toTuple())
        radial = unit(c - center)
        axis = unit(np.cross(t, center - c))
        frame = Frame(_tup(center), _tup(radial), _tup(np.cross(radial, axis)))
        kind, length = Kind.REVOLVE, 0.0
    names = ("l_start", "l_control1", "l_control2", "l_end")
    flat = _flat(frame, np.vstack([c, place.profile]))
    pts = (_point("c", ("c_u", "c_v"), flat[0], scale),) + tuple(
        _point(k, (f"{k}_u", f"{k}_v"), q, scale) for k, q in zip(names, flat[1:], strict=False)
    )
    outline = Outline(pts, (("c", "l_start"), names, ("l_end", "c")))
    dims = {"edge": length} if kind is Kind.EXTRUDE else {}
    return Feature(step, kind, mode, frame, outline, length=length, dims=dims)


def _prism(rf, op: AddSubPrism, step: int, scale: float) -> Feature:
    pts3 = on_face_plane(op.polygon, rf, scale, "prism polygon c")
    n = rf.normal
    if rf.surface is None:
        origin = pts3.mean(axis=0)
        u, _ = plane_basis(n)
    else:  # the tangent plane T at p_f, u along the surface's generatrix
        origin = rf.plane_point
        u = rf.surface.axis - (rf.surface.axis @ n) * n
        u = u / np.linalg.norm(u)
    frame = Frame(_tup(origin), _tup(u), _tup(n))
    flat = _flat(frame, pts3)
    names = tuple(f"c{k + 1}" for k in range(len(flat)))
    pts = tuple(
        _point(k, (f"{k}_u", f"{k}_v"), q, scale) for k, q in zip(names, flat, strict=False)
    )
    segments = tuple((a, b) for a, b in zip(names, names[1:] + names[:1], strict=False))
    outline = Outline(pts, segments)
    back, clip = 0.0, None
    if rf.surface is not None:
        back, clip = _reach(rf, op, prism_footprint(pts3), scale, "prism polygon c")
    return Feature(step, Kind.EXTRUDE, op.mode, frame, outline, length=op.d, back=back, clip=clip)


def _sweep(rf, op: Sweep, step: int, scale: float) -> Feature:
    (center,) = on_face_plane([op.center], rf, scale, "sweep centre of c0")
    axis = rf.normal * op.mode.sign
    radial, _ = plane_basis(axis)
    # sketch (u, v) = (r, h); a SUBTRACT's plan pockets along -n, so its sketch's v is -n
    frame = Frame(_tup(center), _tup(radial), _tup(np.cross(radial, axis)))
    ctrl = np.array(op.control_points(), float)
    chord = ctrl[0] + (ctrl[3] - ctrl[0]) * np.array([[1 / 3], [2 / 3]])
    straight = np.allclose(ctrl[1:3], chord, rtol=0, atol=1e-9 * max(op.d, op.r0, op.r1))
    pts = [
        Point("c0", ("r0", None), (op.r0, 0.0)),
        _point("cp1", ("cp1_r", "cp1_h"), ctrl[1], scale),
        _point("cp2", ("cp2_r", "cp2_h"), ctrl[2], scale),
        Point("c1", ("r1", "d"), (op.r1, op.d)),
        Point("top", (None, "d"), (0.0, op.d)),
        Point("bottom", (None, None), (0.0, 0.0)),
    ]
    profile = ("c0", "c1") if straight else ("c0", "cp1", "cp2", "c1")
    if straight:
        pts = [p for p in pts if p.name not in ("cp1", "cp2")]
    clip, back = None, 0.0
    if rf.surface is not None:  # a cylinder of c0 down through T to the surface
        back, clip = _reach(
            rf, op, sweep_footprint(center, rf.normal, op.r0), scale, "sweep circle c0"
        )
        pts[-1] = Point("bottom", (None, "foot_h"), (0.0, -back))
        pts.append(Point("foot", ("r0", "foot_h"), (op.r0, -back)))
        segments = (("bottom", "foot"), ("foot", "c0"), profile, ("c1", "top"), ("top", "bottom"))
    else:
        segments = (("bottom", "c0"), profile, ("c1", "top"), ("top", "bottom"))
    return Feature(step, Kind.REVOLVE, op.mode, frame, Outline(tuple(pts), segments), clip=clip)


def _reach(rf, op, footprint: np.ndarray, scale: float, what: str) -> tuple[float, Clip]:
    """How far behind T (mm, along the primitive's direction) the primitive starts, and
    what trims it (brep/operators.curved_reach)."""
    reach = curved_reach(rf, op, footprint, scale, what)
    surface = rf.surface
    base, r_lo, r_hi, length = surface.bounds(rf.plane_point, reach.extent)
    clip = Clip(
        surface.kind.value, _tup(base), _tup(surface.axis), r_lo, r_hi, length, reach.keep_inside
    )
    return abs(reach.start), clip


def _flat(frame: Frame, pts: np.ndarray) -> np.ndarray:
    q = np.atleast_2d(pts) - np.asarray(frame.origin)
    return np.stack([q @ np.asarray(frame.u), q @ np.asarray(frame.v)], axis=1)


def _point(name: str, dims: tuple[str, str], q, scale: float) -> Point:
    """A point whose coordinates within SAME_REL of 0 are 0 (no dimension)."""
    at = tuple(0.0 if abs(float(x)) <= SAME_REL * scale else float(x) for x in q)
    return Point(name, tuple(d if x != 0.0 else None for d, x in zip(dims, at, strict=False)), at)


def _tup(v) -> Vec3:
    return tuple(float(x) for x in v)


# ----------------------------------------------------------------- building


def feature_tool(feature: Feature, solid: cq.Shape | None = None, clip: bool = True) -> cq.Shape:
    """The solid a feature adds, removes or keeps (cadquery), as the features above say;
    `solid` is the solid before (for a FACE or a THICKNESS). `clip`: trim to the clip
    when it has one (the operators do; a PartDesign feature cannot)."""
    if feature.kind is Kind.BOX:
        return make_box(Box(feature.size))
    if feature.kind is Kind.FACE:
        rf = resolve_face(solid, feature.face, "extrude face f")
        n = rf.normal * (1.0 if feature.mode is Mode.ADD else -1.0)
        return cq.Solid.extrudeLinear(
            rf.face.outerWire(), rf.face.innerWires(), cq.Vector(*(n * feature.length))
        )
    if feature.kind is Kind.THICKNESS:
        rf = resolve_face(solid, feature.face, "shell face f")
        op = Shell(feature.face, feature.length)
        return solid.cut(shell_tool(solid, rf, op, model_scale(solid)))  # the cavity
    wire = outline_wire(feature.frame, feature.outline)
    normal = np.asarray(feature.frame.normal)
    if feature.kind is Kind.REVOLVE:
        o = cq.Vector(*feature.frame.origin)
        tool = cq.Solid.revolve(wire, [], feature.angle, o, o + cq.Vector(*feature.frame.v))
    else:
        sign = 1.0 if feature.mode is not Mode.SUBTRACT else -1.0
        d = np.asarray(feature.direction) if feature.direction else normal * sign
        d = d / abs(float(d @ normal))  # unit length along the normal
        start = wire.translate(cq.Vector(*(-d * feature.back)))
        tool = cq.Solid.extrudeLinear(start, [], cq.Vector(*(d * (feature.length + feature.back))))
    if clip and feature.clip is not None:
        c = feature.clip
        base, axis = cq.Vector(*c.base), cq.Vector(*c.axis)
        inside = (
            cq.Solid.makeCone(c.r_base, c.r_far, c.length, base, axis)
            if c.kind == "cone"
            else cq.Solid.makeCylinder(c.r_base, c.length, base, axis)
        )
        tool = tool.intersect(inside) if c.keep_inside else tool.cut(inside)
    return tool


def apply_feature(feature: Feature, solid: cq.Shape, clip: bool = True) -> cq.Shape:
    """The solid after a feature (other than the box) on `solid`, the solid before: its
    tool combined with it, or its fillet or chamfer built on it (`clip`: as for
    `feature_tool`)."""
    if feature.kind in (Kind.FILLET, Kind.CHAMFER):
        faces = [face_through(solid, *side) for side in feature.sides]
        return fillet_or_chamfer_edges(
            solid,
            edges_at(solid, np.array(feature.edges)),
            feature.dims.get("radius"),
            (feature.dims["d1"], feature.dims["d2"]) if feature.kind is Kind.CHAMFER else None,
            faces,
        )
    return combined(solid, feature_tool(feature, solid, clip), feature.mode)


def face_through(solid: cq.Shape, point: Vec3, normal: Vec3) -> cq.Face:
    """The face of `solid` through `point` whose outward normal there is `normal`."""
    tol = 1e-6 * model_scale(solid)
    at = cq.Vertex.makeVertex(*point)
    for face in solid.Faces():
        on_face = face.distance(at) <= tol
        if on_face and face.normalAt(cq.Vector(*point)).dot(cq.Vector(*normal)) > NORMAL_COS_TOL:
            return face
    raise OperationError(f"no face through {point} with outward normal {normal}")


def outline_wire(frame: Frame, outline: Outline) -> cq.Wire:
    """The outline as a closed wire in the world."""
    world = {p.name: cq.Vector(*frame.to_3d(p.at)) for p in outline.points}
    edges = [
        cq.Edge.makeLine(world[s[0]], world[s[1]])
        if len(s) == 2
        else cq.Edge.makeBezier([world[k] for k in s])
        for s in outline.segments
    ]
    return cq.Wire.assembleEdges(edges)


def combined(solid: cq.Shape, tool: cq.Shape, mode: Mode) -> cq.Shape:
    """`solid` and a feature's `tool` combined by `mode` (REPLACE: the tool alone)."""
    if mode is Mode.REPLACE:
        return tool
    return {Mode.ADD: solid.fuse, Mode.SUBTRACT: solid.cut, Mode.INTERSECT: solid.intersect}[mode](
        tool
    ).clean()


def mismatch(a: cq.Shape, b: cq.Shape) -> float:
    """The volume of the symmetric difference of two solids over b's volume."""
    return (a.cut(b).Volume() + b.cut(a).Volume()) / b.Volume()
