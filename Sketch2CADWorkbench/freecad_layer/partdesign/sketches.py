# SPDX-License-Identifier: LGPL-2.1-or-later
"""A feature plan's outline (brep/features) as a Sketcher sketch, fully constrained.

Every point of the outline gets one constraint per coordinate: on a sketch axis where
the coordinate is 0, Horizontal or Vertical on the line to an earlier point that shares
that dimension, else a DistanceX or DistanceY from the sketch's origin named as the
dimension (`Constraints.d`, `Constraints.r0`, ...). The segments' shared ends are
coincident. A cubic Bezier is a Sketcher B-spline of degree 3 with four poles; its
inner poles are placed by their construction circles (Sketcher's own way of editing
poles), each of weight 1.
"""

import math

import FreeCAD
import Part
import Sketcher

from ...brep.features import Frame, Outline

ROOT, H_AXIS, V_AXIS = (-1, 1), -1, -2  # the sketch's origin point and axes (geometry ids)
START, END, CENTER = 1, 2, 3  # Sketcher's point positions on a geometry


def placement(frame: Frame) -> "FreeCAD.Placement":
    """The placement of a sketch whose plane is `frame` (u, v, normal as its x, y, z)."""
    u, v, n = frame.u, frame.v, frame.normal
    m = FreeCAD.Matrix(u[0], v[0], n[0], frame.origin[0], u[1], v[1], n[1], frame.origin[1])
    m.A31, m.A32, m.A33, m.A34 = u[2], v[2], n[2], frame.origin[2]
    return FreeCAD.Placement(m)


def draw_outline(sketch, outline: Outline) -> None:
    """Add the outline's geometry and constraints to an empty sketch (module docstring)."""
    at = {p.name: FreeCAD.Vector(p.at[0], p.at[1], 0.0) for p in outline.points}
    uses: dict[str, list[tuple[int, int]]] = {p.name: [] for p in outline.points}
    lines: dict[frozenset, int] = {}
    constraints = []
    for seg in outline.segments:
        if len(seg) == 2:
            geo = sketch.addGeometry(Part.LineSegment(at[seg[0]], at[seg[1]]), False)
            lines[frozenset(seg)] = geo
            uses[seg[0]].append((geo, START))
            uses[seg[1]].append((geo, END))
            continue
        curve = Part.BSplineCurve()
        curve.buildFromPolesMultsKnots([at[k] for k in seg], [4, 4], [0.0, 1.0], False, 3)
        geo = sketch.addGeometry(curve, False)
        uses[seg[0]].append((geo, START))
        uses[seg[3]].append((geo, END))
        before = sketch.GeometryCount
        sketch.exposeInternalGeometry(geo)
        poles = _poles(sketch, geo, before)
        # FreeCAD 1.0 and newer fix the poles' weights as they expose them (a Weight and
        # Equal constraints); 0.20 leaves them free
        weighted = {
            g
            for c in sketch.Constraints
            if c.Type in ("Weight", "Equal", "Radius", "Diameter")
            for g in (c.First, c.Second)
        }
        for index, circle in poles.items():
            if circle not in weighted:
                constraints.append(Sketcher.Constraint("Weight", circle, 1.0))
            if index in (1, 2):
                uses[seg[index]].append((circle, CENTER))
    for occurrences in uses.values():
        first = occurrences[0]
        constraints += [Sketcher.Constraint("Coincident", *first, *o) for o in occurrences[1:]]
    named: dict[tuple[int, str], str] = {}  # (coordinate, dimension) -> the point holding it
    dims: list[tuple[object, str]] = []
    for p in outline.points:
        geo, pos = uses[p.name][0]
        if p.dims == (None, None):
            constraints.append(Sketcher.Constraint("Coincident", geo, pos, *ROOT))
            continue
        for axis, dim in enumerate(p.dims):
            if dim is None:  # u = 0 lies on the v axis, v = 0 on the u axis
                constraints.append(
                    Sketcher.Constraint("PointOnObject", geo, pos, V_AXIS if axis == 0 else H_AXIS)
                )
                continue
            held = named.get((axis, dim))
            line = lines.get(frozenset((held, p.name))) if held else None
            if line is not None:
                constraints.append(
                    Sketcher.Constraint("Vertical" if axis == 0 else "Horizontal", line)
                )
                continue
            label = dim if held is None else f"{dim}_{p.name}"
            named.setdefault((axis, dim), p.name)
            kind = "DistanceX" if axis == 0 else "DistanceY"
            dims.append((Sketcher.Constraint(kind, geo, pos, p.at[axis]), label))
    sketch.addConstraint(constraints)
    for constraint, label in dims:
        sketch.renameConstraint(sketch.addConstraint(constraint), label)


def _poles(sketch, bspline: int, since: int) -> dict[int, int]:
    """The construction circles of a B-spline's poles that exposeInternalGeometry added:
    pole index -> geometry id (matched by position: FreeCAD 0.20's constraints do not
    say which pole a circle stands for)."""
    poles = sketch.Geometry[bspline].getPoles()
    out = {}
    for geo in range(since, sketch.GeometryCount):
        shape = sketch.Geometry[geo]
        if isinstance(shape, Part.Circle):
            out[min(range(len(poles)), key=lambda k: (poles[k] - shape.Center).Length)] = geo
    return out


def copy_face(sketch, face) -> None:
    """Add a planar face's edges (outline and holes; world coordinates) to a sketch lying
    in its plane, each fixed by a Block constraint: the outline is what earlier steps
    made, not a parameter of the step that extrudes it. Lines and circular arcs stay
    lines and arcs (counter-clockwise, as Sketcher keeps them); other curves become
    B-splines."""
    to_sketch = sketch.Placement.inverse().toMatrix()
    for edge in face.Edges:
        local = edge.copy()
        local.transformShape(to_sketch)
        first, last = local.Vertexes[0].Point, local.Vertexes[-1].Point
        kind = type(local.Curve).__name__
        if kind in ("Line", "LineSegment"):
            geometry = Part.LineSegment(first, last)
        elif kind == "Circle" and local.isClosed():
            geometry = Part.Circle(local.Curve.Center, FreeCAD.Vector(0, 0, 1), local.Curve.Radius)
        elif kind == "Circle":
            mid = local.valueAt(0.5 * (local.FirstParameter + local.LastParameter))
            center = local.Curve.Center
            circle = Part.Circle(center, FreeCAD.Vector(0, 0, 1), local.Curve.Radius)
            geometry = Part.ArcOfCircle(circle, *_counter_clockwise(center, first, mid, last))
        else:
            geometry = local.toNurbs().Edges[0].Curve
        geo = sketch.addGeometry(geometry, False)
        sketch.addConstraint(Sketcher.Constraint("Block", geo))


def _counter_clockwise(center, a, mid, b) -> tuple[float, float]:
    """The angles (radians, counter-clockwise) spanning the arc from a through mid to b."""
    t_a, t_mid, t_b = (math.atan2(p.y - center.y, p.x - center.x) for p in (a, mid, b))

    def ccw(t0: float, t1: float) -> float:
        return (t1 - t0) % (2 * math.pi)

    if ccw(t_a, t_mid) < ccw(t_a, t_b):
        return t_a, t_a + ccw(t_a, t_b)
    return t_b, t_b + ccw(t_b, t_a)
