# SPDX-License-Identifier: LGPL-2.1-or-later
"""A protocol as a CadQuery or build123d script: readable code that rebuilds the model
with that library's public API and nothing of this project.

One block per step: the step's listing line as a comment, its parameters as named
variables (mm; the names of `brep/features`' dimensions, as the PartDesign conversion
names its sketch constraints), its sketch plane, its outline, and the Boolean. A base
face is found again by a point on it and its outward normal, as the protocol stores it.
The geometry is where the core's replay put each step (`plan_protocol`), so the script
builds the same solid (a shell by OCCT's thick solid with the core's settings, which
neither library's own shell takes, through OCP, which both libraries install); on a
curved face the primitive is trimmed to the face's surface
as the operators trim it.

The blocks, their variables and comments are laid out once (`protocol_script`); a `_Library`
spells each piece in its library's own idiom (CadQuery's `Workplane` paths, build123d's
algebra mode).
"""

from __future__ import annotations

from abc import ABC, abstractmethod

from .features import Clip, Feature, Frame, Kind, Outline, Plan
from .operators import THICK_TOL
from .protocol import Extrude, Mode

# The helper a script with a shell holds: OCCT's thick solid as the core builds it.
HOLLOWED = f'''
from OCP.BRepOffsetAPI import BRepOffsetAPI_MakeThickSolid
from OCP.GeomAbs import GeomAbs_JoinType

try:
    from OCP.TopTools import TopTools_ListOfShape as ShapeList
except ImportError:  # OCP 7.8 (build123d's) keeps OCCT's lists in OCP.collections
    from OCP.collections import List_TopoDS_Shape as ShapeList


def hollowed(solid, face, t):
    """OCCT's shape of `solid` open at `face`, every other face moved t inwards, the
    offset faces joined by intersection (solid and face: OCCT shapes)."""
    opened = ShapeList()
    opened.Append(face)
    builder = BRepOffsetAPI_MakeThickSolid()
    builder.MakeThickSolidByJoin(
        solid, opened, -t, {THICK_TOL}, Intersection=False,
        Join=GeomAbs_JoinType.GeomAbs_Intersection,
    )
    builder.Build()
    return builder.Shape()
'''


class _Library(ABC):
    """How one library writes each piece of a script (subclasses below). The pieces use
    the script's variables: `face`, `d`, `plane`, `profile`, `direction`, `tool`,
    `surface` and the model's (`model`)."""

    header: str  # the script's docstring, imports and helpers; formatted with the title
    footer: str  # `result`, and the volume printed when run
    model: str  # the variable holding the model after each step
    # after the header when a step fillets or chamfers edges of the model: `edges_at`
    # (the edge nearest each point) and `chamfer` (d1 measured on each edge's face)
    edge_helpers: str

    @abstractmethod
    def box(self) -> str:
        """The base box of size lx, ly, lz centred on the origin."""
        ...

    @abstractmethod
    def face_tool(self, curved: bool, normal: str) -> str:
        """A base `face` (outward `normal`) moved d along its normal, or every point of a
        curved one along its normal there."""
        ...

    @abstractmethod
    def combine_by_sign(self) -> str:
        """The model with `tool` added for d > 0, else subtracted."""
        ...

    @abstractmethod
    def plane(self, frame: Frame) -> str:
        """A sketch plane: origin, x along the frame's u, z along its normal."""
        ...

    @abstractmethod
    def profile(self, outline: Outline, offset: str | None) -> list[str]:
        """Lines making `profile`, the outline on `plane` (moved `offset` along its
        normal where given)."""
        ...

    @abstractmethod
    def revolve(self, angle: str) -> str:
        """`profile` revolved `angle` degrees about the plane's y axis."""
        ...

    @abstractmethod
    def extrude(self, length: str, sign: int) -> str:
        """`profile` extruded `length` along the plane's normal times `sign`."""
        ...

    @abstractmethod
    def vector(self, v) -> str:
        """A 3D vector."""
        ...

    @abstractmethod
    def extrude_along(self, length: str) -> str:
        """`profile` extruded along `direction` until `length` along the plane's normal."""
        ...

    @abstractmethod
    def surface(self, clip: Clip) -> str:
        """The cylinder or cone bounded by a curved face's surface."""
        ...

    @abstractmethod
    def trim(self, keep_inside: bool) -> str:
        """The statement trimming `tool` to what lies inside `surface` (keep_inside) or
        outside it."""
        ...

    @abstractmethod
    def combine(self, mode: Mode) -> str:
        """The statement combining `tool` with the model."""
        ...

    @abstractmethod
    def hollow(self) -> str:
        """The statement hollowing the model open at `face` with walls `t` (`hollowed`)."""
        ...


class _CadQuery(_Library):
    header = '''#!/usr/bin/env python3
"""{title}: a Sketch2CAD protocol rebuilt with CadQuery's public API.

One block per step, its parameters as named variables (mm). Needs only cadquery
(pip install cadquery). Run it to print the solid's volume, or import it: `result`
is the solid (a cadquery Solid).
"""

import cadquery as cq


def face_at(solid, point, normal):
    """The face of `solid` through `point` whose outward normal there is `normal`."""
    tol = 1e-6 * max(solid.BoundingBox().DiagonalLength, 1.0)
    at, n = cq.Vector(*point), cq.Vector(*normal)
    for face in solid.Faces():
        on_face = face.distance(cq.Vertex.makeVertex(*point)) <= tol
        if on_face and face.normalAt(at).dot(n) > 0.999999:
            return face
    raise ValueError(f"no face through {{point}} with outward normal {{normal}}")


def combine(solid, tool, mode):
    """`solid` with a step's `tool` added, subtracted, intersected, or replaced by it."""
    if mode == "replace":
        result = tool
    else:
        combine_with = {{"add": solid.fuse, "subtract": solid.cut, "intersect": solid.intersect}}
        result = combine_with[mode](tool)
    solids = result.clean().Solids()
    if len(solids) != 1:
        raise ValueError(f"a {{mode}} gives {{len(solids)}} solids, not one")
    return solids[0]

'''
    footer = """
result = solid

if __name__ == "__main__":
    print(f"volume {result.Volume():.6f} mm^3")
"""
    edge_helpers = '''
def edges_at(solid, points):
    """The edge of `solid` nearest each point (a point on each edge to round)."""
    edges = solid.Edges()
    return [min(edges, key=lambda e: e.distance(cq.Vertex.makeVertex(*p))) for p in points]


def chamfer(solid, d1, d2, edges, faces):
    """`solid` with each edge chamfered, d1 measured on its face in `faces`, d2 on the
    other (cadquery's own chamfer picks that face itself)."""
    from OCP.BRepFilletAPI import BRepFilletAPI_MakeChamfer

    maker = BRepFilletAPI_MakeChamfer(solid.wrapped)
    for edge, face in zip(edges, faces):
        maker.Add(d1, d2, edge.wrapped, face.wrapped)
    return cq.Shape.cast(maker.Shape())

'''
    model = "solid"

    def box(self) -> str:
        return "cq.Solid.makeBox(lx, ly, lz, cq.Vector(-lx / 2, -ly / 2, -lz / 2))"

    def face_tool(self, curved: bool, normal: str) -> str:
        if curved:
            return "face.thicken(d)"
        return f"cq.Solid.extrudeLinear(face.outerWire(), face.innerWires(), cq.Vector{normal} * d)"

    def combine_by_sign(self) -> str:
        return 'solid = combine(solid, tool, "add" if d > 0 else "subtract")'

    def plane(self, frame: Frame) -> str:
        return f"cq.Plane(origin={_v(frame.origin)}, xDir={_v(frame.u)}, normal={_v(frame.normal)})"

    def profile(self, outline: Outline, offset: str | None) -> list[str]:
        start = "cq.Workplane(plane)"
        if offset:
            start += f".transformed(offset=(0, 0, {offset}))"
        segments = list(outline.segments)
        first = segments[0][0]
        out = ["profile = (", f"    {start}", f"    .moveTo({_xy(outline, first)})"]
        if len(segments[-1]) == 2 and segments[-1][1] == first:
            segments = segments[:-1]  # close() draws it
        for s in segments:
            if len(s) == 2:
                out.append(f"    .lineTo({_xy(outline, s[1])})")
            else:
                out.append(f"    .bezier([{_points(outline, s)}])")
        return [*out, "    .close()", ")"]

    def revolve(self, angle: str) -> str:
        return f"profile.revolve({angle}, (0, 0, 0), (0, 1, 0)).val()"

    def extrude(self, length: str, sign: int) -> str:
        return f"profile.extrude({'-' if sign < 0 else ''}{length}).val()"

    def vector(self, v) -> str:
        return f"cq.Vector{_v(v)}"

    def extrude_along(self, length: str) -> str:
        return (
            f"cq.Solid.extrudeLinear(profile.val(), [], direction * ({length} / "
            "abs(direction.dot(plane.zDir))))"
        )

    def surface(self, clip: Clip) -> str:
        c = clip
        if c.kind == "cone":
            return (
                f"cq.Solid.makeCone({_n(c.r_base)}, {_n(c.r_far)}, {_n(c.length)}, "
                f"cq.Vector{_v(c.base)}, cq.Vector{_v(c.axis)})"
            )
        return (
            f"cq.Solid.makeCylinder({_n(c.r_base)}, {_n(c.length)}, cq.Vector{_v(c.base)}, "
            f"cq.Vector{_v(c.axis)})"
        )

    def trim(self, keep_inside: bool) -> str:
        return f"tool = tool.{'intersect' if keep_inside else 'cut'}(surface)"

    def combine(self, mode: Mode) -> str:
        return f'solid = combine(solid, tool, "{mode.value}")'

    def hollow(self) -> str:
        shape = "cq.Shape.cast(hollowed(solid.wrapped, face.wrapped, t))"
        return f'solid = combine(solid, {shape}, "replace")'


class _Build123d(_Library):
    header = '''#!/usr/bin/env python3
"""{title}: a Sketch2CAD protocol rebuilt with build123d's public API (algebra mode).

One block per step, its parameters as named variables (mm). Needs only build123d
(pip install build123d). Run it to print the part's volume, or import it: `result`
is the part (a build123d Part).
"""

from build123d import *


def face_at(part, point, normal):
    """The face of `part` through `point` whose outward normal there is `normal`."""
    tol = 1e-6 * max(part.bounding_box().diagonal, 1.0)
    for face in part.faces():
        on_face = face.distance_to(point) <= tol
        if on_face and face.normal_at(point).dot(Vector(normal)) > 0.999999:
            return face
    raise ValueError(f"no face through {{point}} with outward normal {{normal}}")

'''
    footer = """
result = part

if __name__ == "__main__":
    print(f"volume {result.volume:.6f} mm^3")
"""
    edge_helpers = '''
def edges_at(part, points):
    """The edge of `part` nearest each point (a point on each edge to round)."""
    edges = part.edges()
    return [min(edges, key=lambda e: e.distance_to(Vector(*p))) for p in points]


def chamfer(part, d1, d2, edges, faces):
    """`part` with each edge chamfered, d1 measured on its face in `faces`, d2 on the
    other (build123d's chamfer takes one reference face for all edges)."""
    from OCP.BRepFilletAPI import BRepFilletAPI_MakeChamfer

    maker = BRepFilletAPI_MakeChamfer(part.wrapped)
    for edge, face in zip(edges, faces):
        maker.Add(d1, d2, edge.wrapped, face.wrapped)
    return Solid(maker.Shape())

'''
    model = "part"

    def box(self) -> str:
        return "Box(lx, ly, lz)"

    def face_tool(self, curved: bool, normal: str) -> str:
        if curved:
            return "thicken(face, amount=d)"
        return f"extrude(face, amount=d, dir={normal})"

    def combine_by_sign(self) -> str:
        return "part = part + tool if d > 0 else part - tool"

    def plane(self, frame: Frame) -> str:
        return f"Plane(origin={_v(frame.origin)}, x_dir={_v(frame.u)}, z_dir={_v(frame.normal)})"

    def profile(self, outline: Outline, offset: str | None) -> list[str]:
        on = f"plane.offset({offset})" if offset else "plane"
        make = f"profile = {on} * make_face(outline)"
        segments = outline.segments
        if all(len(s) == 2 for s in segments):  # a polygon
            return [
                f"outline = Polyline({_points(outline, [s[0] for s in segments])}, close=True)",
                make,
            ]
        curves: list[tuple[str, list[str]]] = []  # consecutive lines as one Polyline
        for s in segments:
            if len(s) == 2 and curves and curves[-1][0] == "Polyline":
                curves[-1][1].append(s[1])
            else:
                curves.append(("Polyline" if len(s) == 2 else "Bezier", list(s)))
        body = [
            f"    {'Line' if len(names) == 2 else kind}({_points(outline, names)}),"
            for kind, names in curves
        ]
        return ["outline = [", *body, "]", make]

    def revolve(self, angle: str) -> str:
        return f"revolve(profile, Axis(plane.origin, plane.y_dir), {angle})"

    def extrude(self, length: str, sign: int) -> str:
        return f"extrude(profile, amount={length}, dir={'-' if sign < 0 else ''}plane.z_dir)"

    def vector(self, v) -> str:
        return f"Vector{_v(v)}"

    def extrude_along(self, length: str) -> str:
        return f"extrude(profile, amount={length} / abs(direction.dot(plane.z_dir)), dir=direction)"

    def surface(self, clip: Clip) -> str:
        c = clip
        from_base = "align=(Align.CENTER, Align.CENTER, Align.MIN)"
        solid = (
            f"Cone({_n(c.r_base)}, {_n(c.r_far)}, {_n(c.length)}, {from_base})"
            if c.kind == "cone"
            else f"Cylinder({_n(c.r_base)}, {_n(c.length)}, {from_base})"
        )
        return f"Plane(origin={_v(c.base)}, z_dir={_v(c.axis)}) * {solid}"

    def trim(self, keep_inside: bool) -> str:
        return f"tool {'&' if keep_inside else '-'}= surface"

    def combine(self, mode: Mode) -> str:
        if mode is Mode.REPLACE:
            return "part = tool  # replaces the model"
        return f"part {dict(add='+', subtract='-', intersect='&')[mode.value]}= tool"

    def hollow(self) -> str:
        return "part = Solid(hollowed(part.solids()[0].wrapped, face.wrapped, t))"


LIBRARIES: dict[str, _Library] = {"cadquery": _CadQuery(), "build123d": _Build123d()}


def protocol_script(plan: Plan, title: str, library: str) -> str:
    """The script of a protocol's plan in `library` ("cadquery" or "build123d"; module
    docstring)."""
    lib = LIBRARIES[library]
    lines = [lib.header.format(title=title)]
    if any(f.kind is Kind.THICKNESS for f in plan.features):
        lines.append(HOLLOWED)
    if any(f.kind in (Kind.FILLET, Kind.CHAMFER) for f in plan.features):
        lines.append(lib.edge_helpers)
    listing = plan.protocol.listing().splitlines()
    for feature in plan.features:
        lines.append(f"# Step {listing[feature.step]}")
        if feature.kind is Kind.BOX:
            lx, ly, lz = (_n(x) for x in feature.size)
            lines += [f"lx, ly, lz = {lx}, {ly}, {lz}", f"{lib.model} = {lib.box()}"]
        elif feature.kind is Kind.THICKNESS:
            lines += [
                f"t = {_n(feature.length)}",
                f"face = face_at({lib.model}, {_v(feature.face.point)}, {_v(feature.face.normal)})",
                lib.hollow(),
            ]
        elif feature.kind in (Kind.FILLET, Kind.CHAMFER):
            lines += _rounded(feature, lib)
        elif isinstance(plan.protocol.operations[feature.step - 1], Extrude):
            lines += _extrude(plan.protocol.operations[feature.step - 1], feature, lib)
        else:
            lines += _sketched(feature, lib)
        lines.append("")
    return "\n".join(lines) + lib.footer


def _rounded(feature: Feature, lib: _Library) -> list[str]:
    """A fillet (the model's own `fillet`, OCCT's) or chamfer on the edges through the
    feature's points."""
    m = lib.model
    points = ", ".join(_v(p) for p in feature.edges)
    out = [f"edges = edges_at({m}, [{points}])"]
    if feature.kind is Kind.FILLET:
        return [f"radius = {_n(feature.dims['radius'])}", *out, f"{m} = {m}.fillet(radius, edges)"]
    faces = ", ".join(f"face_at({m}, {_v(p)}, {_v(n)})" for p, n in feature.sides)
    return [
        f"d1, d2 = {_n(feature.dims['d1'])}, {_n(feature.dims['d2'])}",
        *out,
        f"faces = [{faces}]  # where d1 is measured",
        f"{m} = chamfer({m}, d1, d2, edges, faces)",
    ]


def _extrude(op: Extrude, feature: Feature, lib: _Library) -> list[str]:
    face = feature.face
    return [
        f"d = {_n(op.d)}",
        f"face = face_at({lib.model}, {_v(face.point)}, {_v(face.normal)})",
        # a curved side: every point of it moves d along its normal there
        f"tool = {lib.face_tool(face.surface.curved, _v(face.normal))}",
        lib.combine_by_sign(),
    ]


def _sketched(feature: Feature, lib: _Library) -> list[str]:
    frame, outline = feature.frame, feature.outline
    dims = dict(outline.dims)
    if feature.kind is Kind.EXTRUDE:
        length = next((k for k in ("crease", "edge") if k in feature.dims), "d")
        dims[length] = feature.length
        if feature.back:
            dims["reach"] = feature.back
    out = [f"{name} = {_n(value)}" for name, value in dims.items()]
    out.append(f"plane = {lib.plane(frame)}")
    sign = -1 if feature.mode is Mode.SUBTRACT else 1
    back = feature.kind is Kind.EXTRUDE and feature.back
    # an extrusion from behind the plane starts `reach` against its direction
    out += lib.profile(outline, ("reach" if sign < 0 else "-reach") if back else None)
    if feature.kind is Kind.REVOLVE:
        out.append(f"tool = {lib.revolve(_n(feature.angle))}")
    elif feature.direction is not None:
        out.append(f"direction = {lib.vector(feature.direction)}  # along the crease c -> c'")
        out.append(f"tool = {lib.extrude_along(length)}")
    else:
        out.append(f"tool = {lib.extrude(f'({length} + reach)' if back else length, sign)}")
    if feature.clip is not None:
        c = feature.clip
        keep = "inside" if c.keep_inside else "outside"
        out.append(f"# trimmed to f's {c.kind} surface (what lies {keep} it), so the step meets")
        out.append("# the curved face without gap or overlap")
        out.append(f"surface = {lib.surface(c)}")
        out.append(lib.trim(c.keep_inside))
    out.append(lib.combine(feature.mode))
    return out


def _xy(outline: Outline, name: str) -> str:
    """An outline point's coordinates: its dimensions' names (0 where none)."""
    return ", ".join(d or "0" for d in outline.point(name).dims)


def _points(outline: Outline, names) -> str:
    """Outline points as (x, y) tuples."""
    return ", ".join(f"({_xy(outline, k)})" for k in names)


def _n(x: float) -> str:
    return repr(float(x) + 0.0)


def _v(v) -> str:
    return "(" + ", ".join(_n(x) for x in v) + ")"
