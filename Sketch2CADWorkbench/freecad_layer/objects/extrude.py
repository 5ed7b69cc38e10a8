# SPDX-License-Identifier: LGPL-2.1-or-later
"""Extrude: face f moved along its normal by d; a Pad outwards, a Pocket inwards."""

from ...brep.protocol import Extrude
from ..units import length
from .feature import ALL_KINDS, GROUP, OperationFeature, mm

PAD, POCKET = "Pad", "Pocket"
ALL_KINDS.extend([PAD, POCKET])


class ExtrudeFeature(OperationFeature):
    TYPE = "Sketch2CAD::Extrude"
    OPERATION = Extrude
    LABEL = PAD
    KIND_PROPERTIES = ("Offset",)

    def add_operation_properties(self, obj) -> None:
        if "Offset" not in obj.PropertiesList:
            obj.addProperty(
                "App::PropertyDistance",
                "Offset",
                GROUP,
                "d: how far face f moves along its normal (negative: a pocket)",
            )

    @classmethod
    def kind_of(cls, op: Extrude) -> str:
        return PAD if op.d >= 0 else POCKET

    def kind(self, obj) -> str:
        return PAD if mm(obj.Offset) >= 0 else POCKET

    @classmethod
    def reading(cls, op: Extrude) -> str:
        way = "out" if op.d >= 0 else "in"
        return (
            f"{cls.kind_of(op)}: the face moved {way} by {length(abs(op.d))}, "
            f"{cls.on_face(op.face)}"
        )

    def operation(self, obj) -> Extrude:
        return Extrude(self.face(obj), mm(obj.Offset))

    def set_operation(self, obj, op: Extrude) -> None:
        super().set_operation(obj, op)
        obj.Offset = op.d
