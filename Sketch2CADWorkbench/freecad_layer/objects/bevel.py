# SPDX-License-Identifier: LGPL-2.1-or-later
"""Bevel: an edge rounded by profile l drawn across it (along the crease c -> c' from a
corner c of face f, or across an edge of f at c), or, where l is regular, a Fillet of a
radius or a Chamfer of two distances; along the drawn edge, its tangent chain or f's
whole outline."""

import FreeCAD
import numpy as np

from ...brep.protocol import Bevel, EdgeSet
from ..units import length, point
from .feature import ALL_KINDS, GROUP, OperationFeature, mm, retype, tup, vec

ALL_KINDS.extend(["Bevel", "Fillet", "Chamfer"])
ROUND = "Round"
# What the step builds: the drawn profile l itself, a fillet of Radius, or a chamfer of
# Distance1 (on f's side) and Distance2
ROUNDINGS = ["Profile", "Fillet", "Chamfer"]
EDGE_SETS = [e.value for e in EdgeSet]
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
    KIND_PROPERTIES = ("Rounding",)

    def add_operation_properties(self, obj) -> None:
        # files of earlier versions: a freeform profile along its crease (the defaults)
        if "Rounding" not in obj.PropertiesList:
            obj.addProperty(
                "App::PropertyEnumeration",
                "Rounding",
                ROUND,
                "Profile: cut the drawn profile l; Fillet: a constant Radius; Chamfer: "
                "Distance1 on f's side and Distance2 on the other",
            )
            obj.Rounding = ROUNDINGS
        if "Edges" not in obj.PropertiesList:
            obj.addProperty(
                "App::PropertyEnumeration",
                "Edges",
                ROUND,
                "drawn: the edge l is drawn across; chain: every edge continuing it "
                "tangentially; outline: every edge of f's outline that holds it",
            )
            obj.Edges = EDGE_SETS
        if "AcrossEdge" not in obj.PropertiesList:
            obj.addProperty(
                "App::PropertyBool",
                "AcrossEdge",
                ROUND,
                "l is drawn across an edge of f (a straight edge or a circular rim) at c, "
                "from f to the face beyond; off: along the crease c -> c'",
            )
        for name, tip in (
            ("Radius", "The fillet's radius"),
            ("Distance1", "The chamfer's width on f (or on l's start side)"),
            ("Distance2", "The chamfer's width on the other face"),
        ):
            if name not in obj.PropertiesList:
                obj.addProperty("App::PropertyLength", name, ROUND, tip)
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
    def kind_of(cls, op: Bevel) -> str:
        return "Fillet" if op.radius is not None else "Chamfer" if op.distances else "Bevel"

    def kind(self, obj) -> str:
        return {"Profile": "Bevel"}.get(obj.Rounding, obj.Rounding)

    @classmethod
    def reading(cls, op: Bevel) -> str:
        """With its size: the fillet's radius, the chamfer's distances or how far the
        profile l cuts back from c on each side; where it runs."""
        c = np.asarray(op.corner, float)
        a, b = (
            float(np.linalg.norm(np.asarray(p, float) - c)) for p in (op.profile[0], op.profile[-1])
        )
        if op.radius is not None:
            size = f"radius {length(op.radius)}"
        elif op.distances is not None:
            size = f"{length(op.distances[0])} by {length(op.distances[1])}"
        else:
            size = length(a) if abs(a - b) <= 1e-6 * max(a, b) else f"{length(a)} by {length(b)}"
        edges = {
            EdgeSet.DRAWN: "",
            EdgeSet.CHAIN: " and every edge continuing it",
            EdgeSet.OUTLINE: " and the whole outline of the face",
        }[op.edges]
        if op.opposite is None:
            where = f"the edge at {point(op.corner)}{edges}"
        else:
            crease = float(np.linalg.norm(np.asarray(op.opposite, float) - c))
            where = (
                f"the corner at {point(op.corner)} along the {length(crease)} edge to "
                f"{point(op.opposite)}{edges}"
            )
        return f"{cls.kind_of(op)}: {size}, {where} rounded, {cls.on_face(op.face)}"

    def operation(self, obj) -> Bevel:
        rounding = obj.Rounding if "Rounding" in obj.PropertiesList else "Profile"
        across = "AcrossEdge" in obj.PropertiesList and obj.AcrossEdge
        return Bevel(
            self.face(obj),
            tup(obj.Corner),
            None if across else tup(obj.OppositeCorner),
            tuple(tup(getattr(obj, name)) for name, _ in PROFILE_POINTS),
            EdgeSet(obj.Edges) if "Edges" in obj.PropertiesList else EdgeSet.DRAWN,
            mm(obj.Radius) if rounding == "Fillet" else None,
            (mm(obj.Distance1), mm(obj.Distance2)) if rounding == "Chamfer" else None,
        )

    def set_operation(self, obj, op: Bevel) -> None:
        super().set_operation(obj, op)
        obj.Corner = vec(op.corner)
        obj.AcrossEdge = op.opposite is None
        if op.opposite is not None:
            obj.OppositeCorner = vec(op.opposite)
        for (name, _), p in zip(PROFILE_POINTS, op.profile, strict=False):
            setattr(obj, name, vec(p))
        obj.Edges = op.edges.value
        if op.radius is not None:
            obj.Radius = op.radius
        if op.distances is not None:
            obj.Distance1, obj.Distance2 = op.distances
        obj.Rounding = self.kind_of(op) if op.regular else "Profile"
