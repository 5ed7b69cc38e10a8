# SPDX-License-Identifier: LGPL-2.1-or-later
"""A protocol as a CadQuery script: readable code that rebuilds the model with
CadQuery's public API and nothing of this project.

One block per step: the step's listing line as a comment, its parameters as named
variables (mm; the names of `brep/features`' dimensions, as the PartDesign conversion
names its sketch constraints), its sketch plane, its outline, and the Boolean. A base
face is found again by a point on it and its outward normal, as the protocol stores it.
The geometry is where the core's replay put each step (`plan_protocol`), so the script
builds the same solid; on a curved face the primitive is trimmed to the face's surface
as the operators trim it.
"""

from __future__ import annotations

from .features import Feature, Kind, Outline, Plan
from .protocol import Extrude, Mode

HEADER = '''#!/usr/bin/env python3
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

# Added after the header when a step fillets or chamfers edges of the solid before it.
EDGE_HELPERS = '''
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

FOOTER = """
result = solid

if __name__ == "__main__":
    print(f"volume {result.Volume():.6f} mm^3")
"""


def cadquery_script(plan: Plan, title: str) -> str:
    """The CadQuery script of a protocol's plan (module docstring)."""
    lines = [HEADER.format(title=title)]
    if any(f.kind in (Kind.FILLET, Kind.CHAMFER) for f in plan.features):
        lines.append(EDGE_HELPERS)
    listing = plan.protocol.listing().splitlines()
    for feature in plan.features:
        lines.append(f"# Step {listing[feature.step]}")
        if feature.kind is Kind.BOX:
            lines += _box(feature)
        elif feature.kind in (Kind.FILLET, Kind.CHAMFER):
            lines += _rounded(feature)
        elif isinstance(plan.protocol.operations[feature.step - 1], Extrude):
            lines += _extrude(plan.protocol.operations[feature.step - 1], feature)
        else:
            lines += _sketched(feature)
        lines.append("")
    return "\n".join(lines) + FOOTER


def _box(feature: Feature) -> list[str]:
    lx, ly, lz = (_n(x) for x in feature.size)
    return [
        f"lx, ly, lz = {lx}, {ly}, {lz}",
        "solid = cq.Solid.makeBox(lx, ly, lz, cq.Vector(-lx / 2, -ly / 2, -lz / 2))",
    ]


def _rounded(feature: Feature) -> list[str]:
    points = ", ".join(_v(p) for p in feature.edges)
    out = [f"edges = edges_at(solid, [{points}])"]
    if feature.kind is Kind.FILLET:
        return [
            f"radius = {_n(feature.dims['radius'])}",
            *out,
            "solid = solid.fillet(radius, edges)",
        ]
    faces = ", ".join(f"face_at(solid, {_v(p)}, {_v(n)})" for p, n in feature.sides)
    return [
        f"d1, d2 = {_n(feature.dims['d1'])}, {_n(feature.dims['d2'])}",
        *out,
        f"faces = [{faces}]  # where d1 is measured",
        "solid = chamfer(solid, d1, d2, edges, faces)",
    ]


def _extrude(op: Extrude, feature: Feature) -> list[str]:
    face = feature.face
    out = [
        f"d = {_n(op.d)}",
        f"face = face_at(solid, {_v(face.point)}, {_v(face.normal)})",
    ]
    if face.surface.curved:  # every point of the side moves d along its normal there
        out.append("tool = face.thicken(d)")
    else:
        out.append(
            f"tool = cq.Solid.extrudeLinear(face.outerWire(), face.innerWires(), "
            f"cq.Vector{_v(face.normal)} * d)"
        )
    out.append('solid = combine(solid, tool, "add" if d > 0 else "subtract")')
    return out


def _sketched(feature: Feature) -> list[str]:
    frame, outline = feature.frame, feature.outline
    dims = dict(outline.dims)
    if feature.kind is Kind.EXTRUDE:
        length = next((k for k in ("crease", "edge") if k in feature.dims), "d")
        dims[length] = feature.length
        if feature.back:
            dims["reach"] = feature.back
    out = [f"{name} = {_n(value)}" for name, value in dims.items()]
    out.append(
        f"plane = cq.Plane(origin={_v(frame.origin)}, xDir={_v(frame.u)}, "
        f"normal={_v(frame.normal)})"
    )
    start = "cq.Workplane(plane)"
    sign = -1 if feature.mode is Mode.SUBTRACT else 1
    if feature.kind is Kind.EXTRUDE and feature.back:  # from behind the plane
        start += f".transformed(offset=(0, 0, {'' if sign < 0 else '-'}reach))"
    out += ["profile = (", f"    {start}", *_path(outline), ")"]
    if feature.kind is Kind.REVOLVE:
        out.append(f"tool = profile.revolve({_n(feature.angle)}, (0, 0, 0), (0, 1, 0)).val()")
    elif feature.direction is not None:
        out += [
            f"direction = cq.Vector{_v(feature.direction)}  # along the crease c -> c'",
            f"tool = cq.Solid.extrudeLinear(profile.val(), [], direction * ({length} / "
            "abs(direction.dot(plane.zDir))))",
        ]
    else:
        total = f"({length} + reach)" if feature.back else length
        out.append(f"tool = profile.extrude({'-' if sign < 0 else ''}{total}).val()")
    if feature.clip is not None:
        c = feature.clip
        keep = "inside" if c.keep_inside else "outside"
        out.append(f"# trimmed to f's {c.kind} surface (what lies {keep} it), so the step meets")
        out.append("# the curved face without gap or overlap")
        if c.kind == "cone":
            make = (
                f"cq.Solid.makeCone({_n(c.r_base)}, {_n(c.r_far)}, {_n(c.length)}, "
                f"cq.Vector{_v(c.base)}, cq.Vector{_v(c.axis)})"
            )
        else:
            make = (
                f"cq.Solid.makeCylinder({_n(c.r_base)}, {_n(c.length)}, cq.Vector{_v(c.base)}, "
                f"cq.Vector{_v(c.axis)})"
            )
        out.append(f"surface = {make}")
        out.append(f"tool = tool.{'intersect' if c.keep_inside else 'cut'}(surface)")
    out.append(f'solid = combine(solid, tool, "{feature.mode.value}")')
    return out


def _path(outline: Outline) -> list[str]:
    """The outline as a Workplane path: moveTo, lineTo and bezier, closed."""

    def xy(name: str) -> str:
        p = outline.point(name)
        return ", ".join(d or "0" for d in p.dims)

    segments = list(outline.segments)
    first = segments[0][0]
    out = [f"    .moveTo({xy(first)})"]
    if len(segments[-1]) == 2 and segments[-1][1] == first:
        segments = segments[:-1]  # close() draws it
    for s in segments:
        if len(s) == 2:
            out.append(f"    .lineTo({xy(s[1])})")
        else:
            out.append(f"    .bezier([{', '.join(f'({xy(k)})' for k in s)}])")
    out.append("    .close()")
    return out


def _n(x: float) -> str:
    return repr(float(x) + 0.0)


def _v(v) -> str:
    return "(" + ", ".join(_n(x) for x in v) + ")"
