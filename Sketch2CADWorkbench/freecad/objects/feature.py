# SPDX-License-Identifier: LGPL-2.1-or-later
"""The shared proxy of every Sketch2CAD feature: a solid rebuilt by the core on recompute."""
import FreeCAD

from ...brep.protocol import FaceRef
from ..shapes import from_part, to_part

GROUP = "Sketch2CAD"


def mm(value) -> float:
    """A length property's value in mm (FreeCAD hands Quantities for lengths)."""
    return float(getattr(value, "Value", value))


def vec(p) -> "FreeCAD.Vector":
    return FreeCAD.Vector(*[float(c) for c in p])


def tup(v) -> tuple:
    return (float(v.x), float(v.y), float(v.z))


class Feature:
    """Proxy base. Subclasses set TYPE and define add_properties/solid.

    execute() delegates the geometry to the core; any error it raises puts the object
    in FreeCAD's error state with that message, and leaves every property as it was.
    """

    TYPE = "Sketch2CAD::Feature"

    def __init__(self, obj):
        obj.Proxy = self
        self.add_properties(obj)

    def add_properties(self, obj) -> None:
        raise NotImplementedError

    def solid(self, obj):
        """The cadquery solid this feature stands for."""
        raise NotImplementedError

    def execute(self, obj):
        obj.Shape = to_part(self.solid(obj))

    # FreeCAD 0.20 pickles proxies with __getstate__; 0.21.2+ and 1.x call dumps/loads.
    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    def dumps(self):
        return None

    def loads(self, state):
        return None


class OperationFeature(Feature):
    """An operation on the previous feature's solid (`Base`), on base face f."""

    def add_properties(self, obj) -> None:
        obj.addProperty("App::PropertyLink", "Base", GROUP,
                        "The previous feature; this operation applies to its solid")
        obj.addProperty("App::PropertyVector", "FacePoint", "Base face f",
                        "A point inside the base face f (mm); the face is found again on "
                        "every recompute, so it follows edits of earlier steps")
        obj.addProperty("App::PropertyVector", "FaceNormal", "Base face f",
                        "The outward normal of the base face f")
        self.add_operation_properties(obj)

    def add_operation_properties(self, obj) -> None:
        raise NotImplementedError

    def face(self, obj) -> FaceRef:
        n = obj.FaceNormal
        if n.Length == 0:
            raise ValueError("FaceNormal must not be the zero vector")
        return FaceRef(tup(obj.FacePoint), tup(n.normalize() if hasattr(n, "normalize")
                                              else n / n.Length))

    def operation(self, obj):
        """The protocol operation the properties describe."""
        raise NotImplementedError

    def set_operation(self, obj, op) -> None:
        """Write a protocol operation into the properties."""
        obj.FacePoint = vec(op.face.point)
        obj.FaceNormal = vec(op.face.normal)

    def solid(self, obj):
        from ...brep.operators import apply_operation
        if obj.Base is None:
            raise ValueError(f"{obj.Label}: no Base feature to apply the operation to")
        if obj.Base.Shape.isNull():
            raise ValueError(f"{obj.Label}: the Base feature {obj.Base.Label} has no solid "
                             "(it failed to build)")
        return apply_operation(from_part(obj.Base.Shape), self.operation(obj))
