# SPDX-License-Identifier: LGPL-2.1-or-later
"""Add/subtract prism: polygon c on face f extruded by d, combined by the option o; a Boss
when it adds, a Hole when it subtracts."""

import FreeCAD

from ...brep.protocol import AddSubPrism, Mode
from ..units import length, point
from .feature import ALL_KINDS, GROUP, CombinedFeature, mm, retype, tup, vec

MODES = [m.value for m in Mode]
MODE_TIP = (
    "o: add (union, outwards), subtract (difference, inwards), intersect, or "
    "replace (keep only the primitive)"
)
POLYGON = "Polygon c"
PRISM_KINDS = {
    Mode.ADD: "Boss",
    Mode.SUBTRACT: "Hole",
    Mode.INTERSECT: "PrismCommon",
    Mode.REPLACE: "PrismOnly",
}
ALL_KINDS.extend(PRISM_KINDS.values())
MAX_VERTICES = 6


def vertex_name(i: int) -> str:
    return f"Vertex{i + 1}"


class PrismFeature(CombinedFeature):
    """The polygon's vertices are the properties Vertex1...VertexN (N = 3 to 6), each a
    position in the user's units (FreeCAD has no list of lengths)."""

    TYPE = "Sketch2CAD::AddSubPrism"
    OPERATION = AddSubPrism
    LABEL = "Boss"
    KIND_PROPERTIES = ("Mode",)
    KINDS = PRISM_KINDS

    def add_operation_properties(self, obj) -> None:
        if "Length" not in obj.PropertiesList:
            obj.addProperty("App::PropertyLength", "Length", GROUP, "d: the prism's length")
        if "Mode" not in obj.PropertiesList:
            obj.addProperty("App::PropertyEnumeration", "Mode", GROUP, MODE_TIP)
            obj.Mode = MODES

    def migrate(self, obj) -> None:
        if "Polygon" in obj.PropertiesList:  # saved by an earlier version: one vector list
            polygon = [FreeCAD.Vector(p) for p in obj.Polygon]
            obj.removeProperty("Polygon")
            self.set_polygon(obj, polygon)
        super().migrate(obj)

    @classmethod
    def reading(cls, op: AddSubPrism) -> str:
        return (
            f"{cls.kind_of(op)} ({op.mode.value}): a {len(op.polygon)}-sided prism "
            f"{length(op.d)} long {cls.on_face(op.face)}; vertices "
            + ", ".join(point(p) for p in op.polygon)
        )

    def polygon(self, obj) -> list:
        """The polygon's vertices (FreeCAD vectors, mm), in order."""
        out = []
        while vertex_name(len(out)) in obj.PropertiesList:
            out.append(getattr(obj, vertex_name(len(out))))
        return out

    def set_polygon(self, obj, points) -> None:
        """Set the vertices, adding or removing Vertex properties to match their number."""
        for i, p in enumerate(points):
            retype(
                obj,
                vertex_name(i),
                "App::PropertyPosition",
                POLYGON,
                f"c: vertex {i + 1} of the base polygon on face f",
            )
            setattr(obj, vertex_name(i), vec(p))
        i = len(points)
        while vertex_name(i) in obj.PropertiesList:
            obj.removeProperty(vertex_name(i))
            i += 1

    def operation(self, obj) -> AddSubPrism:
        return AddSubPrism(
            self.face(obj), tuple(tup(p) for p in self.polygon(obj)), mm(obj.Length), Mode(obj.Mode)
        )

    def set_operation(self, obj, op: AddSubPrism) -> None:
        super().set_operation(obj, op)
        self.set_polygon(obj, op.polygon)
        obj.Length = op.d
        obj.Mode = op.mode.value
