# SPDX-License-Identifier: LGPL-2.1-or-later
"""The base box every Sketch2CAD model starts from."""
from ...brep.protocol import Box
from .feature import GROUP, Feature, mm


class BoxFeature(Feature):
    """An axis-aligned box of Length x Width x Height mm centred on the origin."""

    TYPE = "Sketch2CAD::Box"

    def add_properties(self, obj) -> None:
        for name, tip in (("Length", "along x"), ("Width", "along y"), ("Height", "along z")):
            obj.addProperty("App::PropertyLength", name, GROUP, f"Box size {tip} (mm)")

    def box(self, obj) -> Box:
        return Box((mm(obj.Length), mm(obj.Width), mm(obj.Height)))

    def set_box(self, obj, box: Box) -> None:
        obj.Length, obj.Width, obj.Height = box.size

    def solid(self, obj):
        from ...brep.operators import make_box
        return make_box(self.box(obj))
