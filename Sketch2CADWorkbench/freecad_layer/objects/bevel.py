# SPDX-License-Identifier: LGPL-2.1-or-later
"""Bevel: corner c of face f rounded by profile l along the crease c -> c'."""
from ...brep.protocol import Bevel
from .feature import GROUP, OperationFeature, tup, vec


class BevelFeature(OperationFeature):
    TYPE = "Sketch2CAD::Bevel"
    OPERATION = Bevel
    LABEL = "Bevel"

    def add_operation_properties(self, obj) -> None:
        obj.addProperty("App::PropertyVector", "Corner", GROUP, "c: the corner of f to round (mm)")
        obj.addProperty("App::PropertyVector", "OppositeCorner", GROUP,
                        "c': the other end of the crease from c (mm)")
        obj.addProperty("App::PropertyVectorList", "Profile", GROUP,
                        "l: the 4 control points of the cubic Bezier profile on f (mm)")

    def operation(self, obj) -> Bevel:
        if len(obj.Profile) != 4:
            raise ValueError(f"{obj.Label}: Profile needs 4 control points, has {len(obj.Profile)}")
        return Bevel(self.face(obj), tup(obj.Corner), tup(obj.OppositeCorner),
                     tuple(tup(p) for p in obj.Profile))

    def set_operation(self, obj, op: Bevel) -> None:
        super().set_operation(obj, op)
        obj.Corner, obj.OppositeCorner = vec(op.corner), vec(op.opposite)
        obj.Profile = [vec(p) for p in op.profile]
