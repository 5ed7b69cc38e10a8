# SPDX-License-Identifier: LGPL-2.1-or-later
"""Shell: the solid hollowed out, open at face f, with walls t thick (FreeCAD's Thickness)."""

from ...brep.protocol import Shell
from ..units import length
from .feature import ALL_KINDS, GROUP, OperationFeature, mm

THICKNESS = "Thickness"
ALL_KINDS.append(THICKNESS)


class ShellFeature(OperationFeature):
    TYPE = "Sketch2CAD::Shell"
    OPERATION = Shell
    LABEL = THICKNESS

    def add_operation_properties(self, obj) -> None:
        if "Thickness" not in obj.PropertiesList:
            obj.addProperty(
                "App::PropertyLength",
                "Thickness",
                GROUP,
                "t: the wall thickness; every face but the opened face f moves inwards by it",
            )

    @classmethod
    def reading(cls, op: Shell) -> str:
        return f"{THICKNESS}: walls {length(op.t)} thick, open {cls.on_face(op.face)}"

    def operation(self, obj) -> Shell:
        return Shell(self.face(obj), mm(obj.Thickness))

    def set_operation(self, obj, op: Shell) -> None:
        super().set_operation(obj, op)
        obj.Thickness = op.t
