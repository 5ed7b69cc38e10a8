# SPDX-License-Identifier: LGPL-2.1-or-later
"""Extrude: face f moved along its normal by d."""
from ...brep.protocol import Extrude
from .feature import GROUP, OperationFeature, mm


class ExtrudeFeature(OperationFeature):
    TYPE = "Sketch2CAD::Extrude"
    OPERATION = Extrude
    LABEL = "Extrude"

    def add_operation_properties(self, obj) -> None:
        obj.addProperty("App::PropertyDistance", "Offset", GROUP,
                        "d: how far face f moves along its normal (mm; negative pockets)")

    def operation(self, obj) -> Extrude:
        return Extrude(self.face(obj), mm(obj.Offset))

    def set_operation(self, obj, op: Extrude) -> None:
        super().set_operation(obj, op)
        obj.Offset = op.d
