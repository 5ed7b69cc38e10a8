# SPDX-License-Identifier: LGPL-2.1-or-later
"""The base box every Sketch2CAD model starts from."""

from ...brep.protocol import Box
from .checks import box_side
from .feature import Feature


class BoxFeature(Feature):
    """An axis-aligned box of Length x Width x Height mm centred on the origin."""

    TYPE = "Sketch2CAD::Box"

    def add_properties(self, obj) -> None:
        for name, axis in (("Length", "x"), ("Width", "y"), ("Height", "z")):
            obj.addProperty("App::PropertyLength", name, "Box", f"Box size along {axis} (mm)")

    def box(self, obj) -> Box:
        """The protocol's base box the properties describe."""
        return Box(tuple(box_side(obj, side) for side in ("Length", "Width", "Height")))

    def set_box(self, obj, box: Box) -> None:
        """Write a protocol base box into the properties."""
        obj.Length, obj.Width, obj.Height = box.size

    def solid(self, obj):
        from ...brep.operators import make_box

        return make_box(self.box(obj))
