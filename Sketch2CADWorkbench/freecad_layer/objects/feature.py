# SPDX-License-Identifier: LGPL-2.1-or-later
"""The shared proxies of Sketch2CAD's features: solids rebuilt by the core on recompute.

A feature's FreeCAD properties are its protocol parameters; execute() turns them into the
core's dataclass, lets the core build the solid, and hands it to FreeCAD as BREP. An
exception raised by execute() puts the feature in FreeCAD's error state, with the
exception's message as its status (tree icon, report view), and the later features go
into error after it (FailurePropagation); every feature keeps its property values, so
the user can fix the value.
"""

import contextlib
import re
from dataclasses import replace

import FreeCAD
import numpy as np

from ...brep.protocol import FaceRef, Mode, Surface, describe
from ..shapes import from_part, to_part
from ..units import direction, point
from .checks import refuse_non_finite

GROUP = "Operation"  # property editor group of the operators' parameters
BASE = "Base"  # where FreeCAD and PartDesign show the links to other features
FACE = "Base face f"
SKETCH = "Sketch"  # the strokes the step was read from
# Labels the workbench gave before features were named as FreeCAD users read them
# (files saved by earlier versions): they count as not renamed by the user.
OLD_LABELS = ("Extrude", "Prism", "Sweep")


def mm(value) -> float:
    """A length property's value in mm (FreeCAD hands out Quantities for lengths)."""
    return float(getattr(value, "Value", value))


def vec(p) -> "FreeCAD.Vector":
    """A 3-sequence of floats (mm) as a FreeCAD vector."""
    return FreeCAD.Vector(*[float(c) for c in p])


def tup(v) -> tuple:
    """A FreeCAD vector as the core's (x, y, z) tuple of floats (mm)."""
    return (float(v.x), float(v.y), float(v.z))


def retype(obj, name: str, kind: str, group: str, tip: str, convert=lambda v: v) -> None:
    """Give property `name` the type `kind`, keeping its value (through `convert`): files
    saved by earlier versions of the workbench hold unit-less vectors where lengths are
    now Quantity properties."""
    if name in obj.PropertiesList and obj.getTypeIdOfProperty(name) == kind:
        return
    value = convert(getattr(obj, name)) if name in obj.PropertiesList else None
    if name in obj.PropertiesList:
        obj.removeProperty(name)
    obj.addProperty(kind, name, group, tip)
    if value is not None:
        setattr(obj, name, value)


def unique_label(obj, base: str) -> str:
    """`base`, numbered as FreeCAD numbers names (Hole001) when another object of the
    document has that label (FreeCAD does not number labels set while a file loads)."""
    taken = {o.Label for o in obj.Document.Objects if o != obj}
    label, n = base, 0
    while label in taken:
        n += 1
        label = f"{base}{n:03d}"
    return label


class Proxy:
    """Persistence of a proxy: it holds no state of its own (the properties hold it).

    FreeCAD 0.20 pickles proxies through __getstate__/__setstate__; 0.21.2 and 1.x call
    dumps/loads. The module and class name, saved by FreeCAD, are enough to restore it.
    """

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    def dumps(self):
        return None

    def loads(self, state):
        return None


class Feature(Proxy):
    """A Part::FeaturePython whose Shape is a solid built by the core.

    Subclasses set TYPE (used by the view provider and `find_models`) and define
    `add_properties` and `solid`.
    """

    TYPE = "Sketch2CAD::Feature"

    def __init__(self, obj):
        obj.Proxy = self
        self.add_properties(obj)
        # Parameters are in world coordinates, and execute() would undo a moved Placement.
        obj.setEditorMode("Placement", 2)

    def add_properties(self, obj) -> None:
        raise NotImplementedError

    def solid(self, obj):
        """The cadquery solid this feature stands for."""
        raise NotImplementedError

    def execute(self, obj):
        refuse_non_finite(obj)  # NaN or inf typed into a property: say which, not OCCT
        obj.Shape = to_part(self.solid(obj))

    def onDocumentRestored(self, obj):
        self.migrate(obj)

    def migrate(self, obj) -> None:
        """Bring the properties of a file saved by an earlier version up to date."""


class OperationFeature(Feature):
    """An operation of the protocol applied to the previous feature's solid (`Base`).

    Subclasses set OPERATION (the protocol dataclass they stand for) and LABEL, and
    define `add_operation_properties`, `operation` and `set_operation`.
    """

    OPERATION = None
    LABEL = "Operation"
    KIND_PROPERTIES = ()  # the properties whose value changes the kind (Pad or Pocket...)

    def add_properties(self, obj) -> None:
        obj.addProperty(
            "App::PropertyLink",
            "Base",
            BASE,
            "The previous feature; this operation applies to its solid",
        )
        self.add_face_properties(obj)
        self.add_operation_properties(obj)
        self.add_record_properties(obj)

    def add_face_properties(self, obj) -> None:
        retype(
            obj,
            "FacePoint",
            "App::PropertyPosition",
            FACE,
            "A point inside the base face f; the face is looked up again on every "
            "recompute, so it follows edits of earlier steps",
        )
        if "FaceNormal" not in obj.PropertiesList:
            obj.addProperty(
                "App::PropertyVector",
                "FaceNormal",
                FACE,
                "The outward normal of the base face f (normalised when used)",
            )
        if "FaceSurface" not in obj.PropertiesList:  # files of earlier versions: planar
            obj.addProperty(
                "App::PropertyEnumeration",
                "FaceSurface",
                FACE,
                "The surface f lies on: a plane, or a cylinder's or cone's side "
                "(then the step stands on the tangent plane at FacePoint)",
            )
            obj.FaceSurface = [s.value for s in Surface]

    def add_record_properties(self, obj) -> None:
        """The paper's operator (read only) and the sketch the step was read from."""
        if "Operator" not in obj.PropertiesList:
            obj.addProperty(
                "App::PropertyString",
                "Operator",
                BASE,
                "The paper's operator this step is (Sketch2CAD's protocol)",
            )
            obj.setEditorMode("Operator", 1)
        if "SketchStep" not in obj.PropertiesList:
            obj.addProperty(
                "App::PropertyString",
                "SketchStep",
                SKETCH,
                "The strokes, view and choices the step was read from (JSON, "
                "as a step of a session file); double-click the feature to "
                "read them again",
            )
            obj.setEditorMode("SketchStep", 2)
        if "SketchOffset" not in obj.PropertiesList:
            obj.addProperty(
                "App::PropertyVector",
                "SketchOffset",
                SKETCH,
                "How far (mm) the step moved with edits of earlier steps since its "
                "strokes were drawn: they are shown moved as much when it is edited",
            )
            obj.setEditorMode("SketchOffset", 2)

    def migrate(self, obj) -> None:
        self.add_face_properties(obj)
        self.add_operation_properties(obj)
        self.add_record_properties(obj)
        self.update_kind(obj, rename=obj.Label.rstrip("0123456789") in OLD_LABELS)

    @classmethod
    def kind_of(cls, op) -> str:
        """The name a FreeCAD user reads for `op` (Pad, Pocket, Boss, Hole...): its label
        and the name of its icon."""
        return cls.LABEL

    def kind(self, obj) -> str:
        """The feature's kind from its current values (see `kind_of`)."""
        return self.LABEL

    @classmethod
    def reading(cls, op) -> str:
        """`op` in words and in the user's units, as the Sketch panel shows it (the
        paper's notation stays in the protocol and the command line)."""
        raise NotImplementedError

    @staticmethod
    def on_face(face: FaceRef) -> str:
        kind = f" (a {face.surface.value}'s side)" if face.surface.curved else ""
        return f"on the {direction(face.normal)} face{kind} at {point(face.point)}"

    def update_kind(self, obj, rename: bool = False) -> None:
        """After the Boolean or the offset's sign changed: the paper's operator, the icon,
        and the label too unless the user renamed the feature (or `rename`)."""
        # values being edited: execute() reports them
        with contextlib.suppress(ValueError, TypeError, AttributeError):
            obj.Operator = describe(self.operation(obj)).split(" ", 1)[0]
        kind = self.kind(obj)
        auto = re.fullmatch(rf"({'|'.join(ALL_KINDS)})\d*", obj.Label)
        if (rename or auto) and obj.Label.rstrip("0123456789") != kind:
            obj.Label = unique_label(obj, kind)

    def onChanged(self, obj, prop):
        # Undo, redo and file loading restore the label, the operator and the offset
        # themselves; the view provider changes the icon (ViewProviderSketch2CAD.updateData).
        if obj.Document.Restoring or obj.Document.Transacting or "Restore" in obj.State:
            return
        if prop in self.KIND_PROPERTIES and "Operator" in obj.PropertiesList:
            self.update_kind(obj)
        if prop == "SketchStep" and "SketchOffset" in obj.PropertiesList:
            obj.SketchOffset = FreeCAD.Vector()  # new strokes: drawn where the step is

    def add_operation_properties(self, obj) -> None:
        raise NotImplementedError

    def face(self, obj) -> FaceRef:
        """The base face reference; the normal is normalised unless it already has length 1
        (then it is kept bit for bit, so protocols round-trip exactly)."""
        n = FreeCAD.Vector(obj.FaceNormal)
        big = max(abs(n.x), abs(n.y), abs(n.z))
        if big > 1e150:  # the length of (1e300, 1e300, 0) overflows: scale first
            n = n * (1.0 / big)
        if n.Length < 1e-12:
            raise ValueError(f"{obj.Label}: FaceNormal must not be the zero vector")
        if abs(n.Length - 1.0) > 1e-12:
            n.normalize()
        return FaceRef(tup(obj.FacePoint), tup(n), Surface(obj.FaceSurface))

    def operation(self, obj):
        """The protocol operation the properties describe."""
        raise NotImplementedError

    def set_operation(self, obj, op) -> None:
        """Write a protocol operation into the properties (subclasses add theirs)."""
        obj.FacePoint = vec(op.face.point)
        obj.FaceNormal = vec(op.face.normal)
        obj.FaceSurface = op.face.surface.value
        obj.Operator = describe(op).split(" ", 1)[0]

    def solid(self, obj):
        from ...brep.operators import apply_operation

        if obj.Base is None:
            raise ValueError(f"{obj.Label}: no Base feature to apply the operation to")
        if obj.Base.Shape.isNull() or not obj.Base.isValid():
            raise ValueError(f"{obj.Label}: its Base {obj.Base.Label} failed to build")
        base, op = from_part(obj.Base.Shape), self.operation(obj)
        moved = where_now(base, op)
        if moved is not op:  # an earlier step moved f: the properties show where it is now
            self.set_operation(obj, moved)
            if "SketchOffset" in obj.PropertiesList:
                obj.SketchOffset = obj.SketchOffset + vec(_anchor(moved) - _anchor(op))
            op = moved
        return apply_operation(base, op)


def _anchor(op) -> np.ndarray:
    """The point an operation is placed by: a bevel's corner, else its face point."""
    return np.asarray(op.corner if hasattr(op, "corner") else op.face.point, float)


def where_now(solid, op):
    """`op` as it lies on `solid` now: moved onto its base face where an edit of an earlier
    step moved that face (brep.faces.resolve_face's shift), a bevel's corner found again
    (brep.operators.locate_bevel); `op` itself (the same object) where nothing moved, f is
    curved, or f does not resolve (execute reports that)."""
    from ...brep.faces import resolve_face
    from ...brep.operators import locate_bevel
    from ...brep.protocol import Bevel, OperationError

    if op.face.surface.curved:
        return op
    try:
        t = resolve_face(solid, op.face).offset
        found = locate_bevel(solid, op) if isinstance(op, Bevel) else op
    except OperationError:
        return op

    def move(p):
        return tuple(float(c) for c in np.asarray(p, float) + t)

    fields = {"face": replace(op.face, point=move(op.face.point))} if np.any(t) else {}
    if isinstance(op, Bevel):
        before, after = (
            np.array([b.corner, *b.profile, *([] if b.across else [b.opposite])], float)
            for b in (op, found)
        )
        if not np.allclose(before, after, rtol=0, atol=1e-7):
            fields.update(corner=found.corner, opposite=found.opposite, profile=found.profile)
    elif fields and hasattr(op, "polygon"):
        fields["polygon"] = tuple(move(p) for p in op.polygon)
    elif fields and hasattr(op, "center"):
        fields["center"] = move(op.center)
    return replace(op, **fields) if fields else op


# Every kind's name (filled by the operators' modules): a label that is one of these, with
# FreeCAD's number, was given by the workbench.
ALL_KINDS = list(OLD_LABELS)


class CombinedFeature(OperationFeature):
    """A feature whose kind follows its Mode property (prisms, sweeps): KINDS maps each
    Mode to the name a FreeCAD user reads."""

    KINDS: dict

    @classmethod
    def kind_of(cls, op) -> str:
        return cls.KINDS[op.mode]

    def kind(self, obj) -> str:
        return self.KINDS[Mode(obj.Mode)]


class FailurePropagation:
    """A document observer: after a recompute, every step after a failed one is rebuilt
    too, so that it goes into error ("its Base ... failed to build") instead of keeping
    the solid it had before the edit (FreeCAD does not recompute what depends on a failed
    object, and would show the later steps as up to date)."""

    def slotRecomputedDocument(self, doc):
        from ..queries import features, find_models

        for model in find_models(doc):
            chain = features(model)
            failed = next((i for i, o in enumerate(chain) if not o.isValid()), None)
            if failed is not None:
                for obj in chain[failed + 1 :]:
                    if obj.isValid():
                        obj.recompute()


OBSERVER = FailurePropagation()
FreeCAD.addDocumentObserver(OBSERVER)  # once: this module is imported once per session
