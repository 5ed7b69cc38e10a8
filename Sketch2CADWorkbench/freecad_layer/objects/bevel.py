# SPDX-License-Identifier: LGPL-2.1-or-later
"""Bevel: corner c of face f rounded by profile l along the crease c -> c'."""

import FreeCAD
import numpy as np

from ...brep.protocol import Bevel
from ..units import length, point
from .feature import ALL_KINDS, GROUP, OperationFeature, retype, tup, vec

ALL_KINDS.append("Bevel")
PROFILE = "Profile l"
# l's four control points, each a position in the user's units (FreeCAD has no list of
# lengths)
PROFILE_POINTS = (
    ("ProfileStart", "l: the profile's start, on one edge of f at c"),
    ("ProfileControl1", "l: the profile's first inner control point"),
    ("ProfileControl2", "l: the profile's second inner control point"),
    ("ProfileEnd", "l: the profile's end, on the other edge of f at c"),
)


class BevelFeature(OperationFeature):
    TYPE = "Sketch2CAD::Bevel"
    OPERATION = Bevel
    LABEL = "Bevel"

    def add_operation_properties(self, obj) -> None:
        retype(obj, "Corner", "App::PropertyPosition", GROUP, "c: the corner of f to round")
        retype(
            obj,
            "OppositeCorner",
            "App::PropertyPosition",
            GROUP,
            "c': the other end of the crease from c",
        )
        for name, tip in PROFILE_POINTS:
            if name not in obj.PropertiesList:
                obj.addProperty("App::PropertyPosition", name, PROFILE, tip)

    def migrate(self, obj) -> None:
        old = [FreeCAD.Vector(p) for p in obj.Profile] if "Profile" in obj.PropertiesList else None
        if old is not None:  # saved by an earlier version: one vector list
            obj.removeProperty("Profile")
        super().migrate(obj)
        if old is not None and len(old) == len(PROFILE_POINTS):
            for (name, _), p in zip(PROFILE_POINTS, old, strict=False):
                setattr(obj, name, p)

    @classmethod
    def reading(cls, op: Bevel) -> str:
        """With its size: how far the profile l cuts back along each edge of f from c, and
        the crease's length."""
        c = np.asarray(op.corner, float)
        a, b = (
            float(np.linalg.norm(np.asarray(p, float) - c)) for p in (op.profile[0], op.profile[-1])
        )
        crease = float(np.linalg.norm(np.asarray(op.opposite, float) - c))
        size = length(a) if abs(a - b) <= 1e-6 * max(a, b) else f"{length(a)} by {length(b)}"
        return (
            f"Bevel: {size}, the corner at {point(op.corner)} rounded along the "
            f"{length(crease)} edge to {point(op.opposite)}, {cls.on_face(op.face)}"
        )

    def operation(self, obj) -> Bevel:
        return Bevel(
            self.face(obj),
            tup(obj.Corner),
            tup(obj.OppositeCorner),
            tuple(tup(getattr(obj, name)) for name, _ in PROFILE_POINTS),
        )

    def set_operation(self, obj, op: Bevel) -> None:
        super().set_operation(obj, op)
        obj.Corner, obj.OppositeCorner = vec(op.corner), vec(op.opposite)
        for (name, _), p in zip(PROFILE_POINTS, op.profile, strict=False):
            setattr(obj, name, vec(p))
