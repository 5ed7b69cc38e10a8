# SPDX-License-Identifier: LGPL-2.1-or-later
"""A protocol as a CadQuery script: readable code that rebuilds the model with
CadQuery's public API and nothing of this project.

One block per step: the step's listing line as a comment, its parameters as named
variables (mm; the names of `brep/features`' dimensions, as the PartDesign conversion
names its sketch constraints), its sketch plane, its outline, and the Boolean. A base
face is found again by a point on it and its outward normal, as the protocol stores it.
The geometry is where the core's replay put each step (`plan_protocol`), so the script
builds the same solid (a shell by OCCT's thick solid with the core's settings, which
cadquery's own shell does not take); on a curved face the primitive is trimmed to the
face's surface as the operators trim it.
"""

from __future__ import annotations

from .features import Feature, Kind, Outline, Plan
from .operators import THICK_TOL
from .protocol import Extrude, Mode

HEADER = '''#!/usr/bin/env python3
"""{title}: a Sketch2CAD protocol rebuilt with CadQuery's public API.

One block per step, its parameters as named variables (mm). Needs only cadquery
(pip install cadquery). Run it to print the solid's volume, or import it: `result`
is the solid (a cadquery Solid).
"""

import cadquery as cq
from OCP.BRepOffsetAPI import BRepOffsetAPI_MakeThickSolid
from OCP.GeomAbs import GeomAbs_JoinType
from OCP.TopTools import TopTools_ListOfShape


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


def hollowed(solid, face, t):
    """`solid` open at `face`, every other face moved t inwards: OCCT's thick solid, its
    offset faces joined by intersection (cadquery's shell with these settings)."""
    opened = TopTools_ListOfShape()
    opened.Append(face.wrapped)
    builder = BRepOffsetAPI_MakeThickSolid()
    builder.MakeThickSolidByJoin(
        solid.wrapped, opened, -t, {tol}, Intersection=False,
        Join=GeomAbs_JoinType.GeomAbs_Intersection,
    )
    builder.Build()
    return cq.Shape.cast(builder.Shape())

'''

FOOTER = """
result = solid

if __name__ == "__main__":
    print(f"volume {result.Volume():.6f} mm^3")
"""


def cadquery_script(plan: Plan, title: str) -> str:
    """The CadQuery script of a protocol's plan (module docstring)."""
    lines = [HEADER.format(title=title, tol=THICK_TOL)]
    listing = plan.protocol.listing().splitlines()
    for feature in plan.features:
        lines.append(f"# Step {listing[feature.step]}")
        if feature.kind is Kind.BOX:
            lines += _box(feature)
        elif feature.kind is Kind.THICKNESS:
            lines += _thickness(feature)
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


def _thickness(feature: Feature) -> list[str]:
    face = feature.face
    return [
        f"t = {_n(feature.length)}",
        f"face = face_at(solid, {_v(face.point)}, {_v(face.normal)})",
        'solid = combine(solid, hollowed(solid, face, t), "replace")',
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
        length = "d" if "crease" not in feature.dims else "crease"
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
