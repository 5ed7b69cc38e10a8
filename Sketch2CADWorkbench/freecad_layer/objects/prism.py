# SPDX-License-Identifier: LGPL-2.1-or-later
"""Add/subtract prism: polygon c on face f extruded by d, combined by the option o."""
from ...brep.protocol import AddSubPrism, Mode
from .feature import GROUP, OperationFeature, mm, tup, vec

MODES = [m.value for m in Mode]
MODE_TIP = ("o: add (union, outwards), subtract (difference, inwards), intersect, or "
            "replace (keep only the primitive)")


class PrismFeature(OperationFeature):
    TYPE = "Sketch2CAD::AddSubPrism"
    OPERATION = AddSubPrism
    LABEL = "Prism"

    def add_operation_properties(self, obj) -> None:
        obj.addProperty("App::PropertyVectorList", "Polygon", GROUP,
                        "c: the 3 to 6 vertices of the base polygon on f (mm)")
        obj.addProperty("App::PropertyLength", "Length", GROUP, "d: the prism's length (mm)")
        obj.addProperty("App::PropertyEnumeration", "Mode", GROUP, MODE_TIP)
        obj.Mode = MODES

    def operation(self, obj) -> AddSubPrism:
        return AddSubPrism(self.face(obj), tuple(tup(p) for p in obj.Polygon), mm(obj.Length),
                           Mode(obj.Mode))

    def set_operation(self, obj, op: AddSubPrism) -> None:
        super().set_operation(obj, op)
        obj.Polygon = [vec(p) for p in op.polygon]
        obj.Length = op.d
        obj.Mode = op.mode.value
