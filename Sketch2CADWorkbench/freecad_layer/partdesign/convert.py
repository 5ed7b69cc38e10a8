# SPDX-License-Identifier: LGPL-2.1-or-later
"""A protocol (or a Sketch2CAD model) as a `PartDesign::Body` of native features.

One feature per step, named as the workbench names it (Box, Pad, Pocket, Boss, Hole,
Revolution, Groove, Bevel...), built from the step's plan (brep/features):

- the base box: an AdditiveBox (Length, Width, Height);
- an extrusion of a planar face: a Pad or Pocket of that face of the feature before
  (PartDesign pads a planar face as it pads a sketch), Length |d|;
- a prism, a bevel: a sketch on f's plane padded or pocketed (a bevel along its crease);
- a fillet or chamfer (a bevel whose profile is regular): a PartDesign::Fillet (Radius)
  or PartDesign::Chamfer (two distances, Size and Size2) on the same edges of the
  feature before; a freeform profile drawn across an edge: its sketch, in the plane
  normal to the edge, padded or pocketed along a straight edge or revolved or grooved
  around a rim;
- a sweep: a sketch in a plane through the axis, revolved (Revolution) or grooved;
- a shell: a Thickness of the feature before, its opened face f the face removed, Value
  t inwards, its offset faces joined by intersection as the core joins them;
- an extrusion of a cylinder's or cone's side: the band between the side and its offset,
  revolved over the side's span;
- a prism or sweep on a curved side: its sketch on the tangent plane (a sweep's in a
  plane through its axis), padded or revolved from far enough behind it to meet the wall.

Sketches are fully constrained by the step's parameters as named dimensions
(sketches.py). On FreeCAD 1.0 they are attached to the planar face they stand on, and a
face's extrusion pads that face, so that an edit of an earlier step moves them
(`FOLLOW_FACES`); elsewhere they stand in the Body's frame (attached to its XY plane with
the step's placement as offset) and a face's extrusion pads a copy of its outline.

Each feature is checked against the core's solid of its step: the Body's solid must have
the same volume (1e-6 relative) and a symmetric difference below 1e-6 of it. A step that
PartDesign cannot express exactly (an intersection with a primitive, a primitive on a
curved side that reaches through a hollow, or any feature that does not match) is kept
as the core's solid, a `Part::Feature` that becomes the BaseFeature of a new Body, the
reason in its `NotNative` property; the later steps are native features of that Body.
A "replace by" step starts a new Body (nothing before it is left in the solid). The last
Body is the model; the earlier ones are hidden.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import FreeCAD
import Part

from ...brep.faces import OperationError
from ...brep.features import Feature, Kind, Plan, plan_protocol
from ...brep.protocol import Mode, Protocol
from ..make.make_model import FEATURE_OF_OPERATION
from ..shapes import to_part
from .sketches import copy_face, draw_outline, placement

TOL = 1e-6  # relative volume and symmetric difference a native feature must meet
# the PartDesign type of each kind of feature, adding and removing
TYPES = {
    (Kind.FACE, True): "PartDesign::Pad",
    (Kind.FACE, False): "PartDesign::Pocket",
    (Kind.EXTRUDE, True): "PartDesign::Pad",
    (Kind.EXTRUDE, False): "PartDesign::Pocket",
    (Kind.REVOLVE, True): "PartDesign::Revolution",
    (Kind.REVOLVE, False): "PartDesign::Groove",
}
EDGE_TYPES = {Kind.FILLET: "PartDesign::Fillet", Kind.CHAMFER: "PartDesign::Chamfer"}
NOT_NATIVE = "NotNative"  # the property that says why a step is kept as a solid
# Whether sketches are attached to the faces they stand on (and faces padded directly),
# so that an edit of an earlier step moves them. Only where the edits of
# tests/freecad/test_partdesign.py (one dimension per feature, the base box's height
# among them) kept every such reference: FreeCAD 1.0. FreeCAD 0.20 renumbered a
# Revolution's faces when the box's height changed, and 1.1.3 lost a sketch's face on a
# Revolution when that Revolution's height changed ("subshape not found"); there every
# sketch stands in the Body's frame.
FOLLOW_FACES = tuple(int(x) for x in FreeCAD.Version()[:2]) == (1, 0)
LAST: dict = {}  # document name -> its last conversion (the GUI command reports it)


@dataclass
class Step:
    """How one step was converted: `native` (a PartDesign feature matching the core's
    solid) or not, with the reason; `mismatch` is the symmetric difference over the
    model's volume (None where not measured)."""

    step: int
    operator: str
    label: str
    native: bool
    reason: str = ""
    mismatch: float | None = None
    feature: str = ""  # the name of its feature object (a Part::Feature when not native)
    sketch: str = ""  # the name of its sketch, if it has one


@dataclass
class Conversion:
    """The Bodies made (the last one is the model) and each step's outcome."""

    bodies: list = field(default_factory=list)
    steps: list[Step] = field(default_factory=list)

    @property
    def body(self):
        return self.bodies[-1]


def convert_model(model) -> Conversion:
    """A Sketch2CAD model of the document as PartDesign Bodies beside it (labelled after
    it); the model is hidden, the Bodies are the last objects of the document.

    Raises:
        OperationError: a step of the model does not build.
    """
    from ..queries import protocol_from_model

    conversion = convert_protocol(model.Document, protocol_from_model(model), f"{model.Label}Body")
    if FreeCAD.GuiUp:
        model.ViewObject.Visibility = False
    return conversion


def convert_protocol(doc, protocol: Protocol, label: str = "Body") -> Conversion:
    """The protocol as PartDesign Bodies in `doc`, recomputed (module docstring).

    Raises:
        OperationError: a step of the protocol does not build (the document keeps what
            was added before).
    """
    plan = plan_protocol(protocol)
    out = Conversion()
    _new_body(doc, out, label)
    for feature in plan.features:
        op = protocol.operations[feature.step - 1] if feature.step else None
        name = "Box" if op is None else FEATURE_OF_OPERATION[op.type].kind_of(op)
        operator = "box" if op is None else op.type.value
        if feature.mode is Mode.REPLACE:
            _new_body(doc, out, label)  # nothing before it stays in the solid
        reason, gap, added = _native(doc, out.body, plan, feature, name)
        if reason:
            added = [_keep_solid(doc, out, plan, feature, name, reason, label)]
        sketch = next((o.Name for o in added if o.TypeId == "Sketcher::SketchObject"), "")
        out.steps.append(
            Step(feature.step, operator, name, not reason, reason, gap, added[-1].Name, sketch)
        )
    doc.recompute()
    if FreeCAD.GuiUp:
        for body in out.bodies[:-1]:
            body.ViewObject.Visibility = False
    LAST[doc.Name] = out
    return out


def _new_body(doc, out: Conversion, label: str, base=None):
    body = doc.addObject("PartDesign::Body", "Body")
    body.Label = label
    if base is not None:
        body.BaseFeature = base
    out.bodies.append(body)
    return body


def _native(doc, body, plan: Plan, feature: Feature, name: str) -> tuple[str, float | None, list]:
    """Add the step's native feature to `body` and check it: "" when it matches the core,
    else the reason (the feature is then removed again); the mismatch measured; the
    objects added (its sketch, then the feature)."""
    if feature.mode is Mode.INTERSECT:
        return (
            "PartDesign has no feature that keeps only the common part of the Body and a "
            "sketched primitive",
            None,
            [],
        )
    added = []
    try:
        tip = _add_feature(doc, body, feature, name, added)
        if "Refine" in tip.PropertiesList:
            # coplanar faces merged, as the core merges them after every Boolean: a later
            # step's face is then the same face (a pad's side and the box's are one)
            tip.Refine = True
        doc.recompute()
        if not tip.isValid() or tip.Shape.isNull():
            raise OperationError(f"FreeCAD's {tip.TypeId} fails: {tip.getStatusString()}")
        gap = _mismatch(tip.Shape, to_part(plan.solids[feature.step]))
    except (OperationError, Part.OCCError, ValueError, RuntimeError) as e:
        _remove(doc, body, added)
        return f"the PartDesign feature cannot be built: {e}", None, []
    if gap > TOL:
        _remove(doc, body, added)
        why = (
            "the primitive reaches through the curved wall into a hollow; PartDesign cannot "
            "trim it to the surface"
            if feature.clip is not None
            else "the PartDesign feature's solid differs from the step's"
        )
        return f"{why} (symmetric difference {gap:.3g} of the volume)", gap, []
    return "", gap, added


def _mismatch(shape, core) -> float:
    """Volume of the symmetric difference over the core's volume; volumes that differ by
    more than TOL count in full."""
    volume = core.Volume
    if abs(shape.Volume - volume) > TOL * volume:
        return abs(shape.Volume - volume) / volume
    return (shape.cut(core).Volume + core.cut(shape).Volume) / volume


def _remove(doc, body, objects) -> None:
    for obj in reversed(objects):
        if obj in body.Group:
            body.removeObject(obj)
        doc.removeObject(obj.Name)
    doc.recompute()


def _add_feature(doc, body, feature: Feature, name: str, added: list):
    """The native feature of `feature` at the end of `body` (with its sketch); every
    object made is appended to `added`."""
    if feature.kind is Kind.THICKNESS:
        previous = body.Tip if body.Tip is not None else body.BaseFeature
        obj = body.newObject("PartDesign::Thickness", name)
        added.append(obj)
        obj.Base = (previous, [_face_name(previous.Shape, feature)])
        obj.Value = feature.length
        obj.Join = "Intersection"
        obj.Reversed = True  # inwards: PartDesign thickens outwards unless reversed
        return obj
    if feature.kind is Kind.BOX:
        box = body.newObject("PartDesign::AdditiveBox", name)
        added.append(box)
        lx, ly, lz = feature.size
        box.Length, box.Width, box.Height = lx, ly, lz
        box.Placement = FreeCAD.Placement(
            FreeCAD.Vector(-lx / 2, -ly / 2, -lz / 2), FreeCAD.Rotation()
        )
        return box
    adds = feature.mode is not Mode.SUBTRACT
    previous = body.Tip if body.Tip is not None else body.BaseFeature
    if feature.kind in EDGE_TYPES:
        return _edge_feature(body, previous, feature, name, added)
    face = _face_name(previous.Shape, feature) if feature.kind is Kind.FACE else ""
    if face and FOLLOW_FACES:  # PartDesign pads a planar face as it pads a sketch
        obj = body.newObject(TYPES[(Kind.FACE, adds)], name)
        added.append(obj)
        obj.Profile = (previous, [face])
        obj.Length = feature.length
        return obj
    sketch = body.newObject("Sketcher::SketchObject", f"{name}Sketch")
    added.append(sketch)
    if face:  # a sketch holding the face's outline, on its plane
        _attach(doc, body, sketch, previous, face_frame(feature))
        copy_face(sketch, previous.Shape.getElement(face))
    else:
        _attach(doc, body, sketch, previous, feature)
        draw_outline(sketch, feature.outline)
    obj = body.newObject(TYPES[(Kind.EXTRUDE if face else feature.kind, adds)], name)
    added.append(obj)
    obj.Profile = sketch
    if feature.kind is Kind.REVOLVE:
        obj.ReferenceAxis = (sketch, ["V_Axis"])
        obj.Angle = feature.angle
    else:
        obj.Length = feature.length
        if feature.back and "SideType" in obj.PropertiesList:  # FreeCAD 1.1 and newer
            obj.SideType, obj.Type2, obj.Length2 = "Two sides", "Length", feature.back
        elif feature.back:
            obj.Type, obj.Length2 = "TwoLengths", feature.back
        if feature.direction is not None:
            obj.UseCustomVector = True
            obj.Direction = FreeCAD.Vector(*feature.direction)
            obj.AlongSketchNormal = True
    sketch.Visibility = False
    return obj


def _edge_feature(body, previous, feature: Feature, name: str, added: list):
    """A PartDesign::Fillet or Chamfer on the edges of `previous` through the feature's
    points; a chamfer's FlipDirection set so that Size is measured on the face where
    the step measures d1 (FreeCAD takes one face of each edge, the same for all edges:
    where that differs from the step's, the check finds the mismatch)."""
    shape = previous.Shape
    names = [_edge_name(shape, p) for p in feature.edges]
    obj = body.newObject(EDGE_TYPES[feature.kind], name)
    added.append(obj)
    obj.Base = (previous, names)
    if feature.kind is Kind.FILLET:
        obj.Radius = feature.dims["radius"]
        return obj
    obj.ChamferType = "Two distances"
    obj.Size, obj.Size2 = feature.dims["d1"], feature.dims["d2"]
    point, normal = feature.sides[0]
    edge = shape.getElement(names[0])
    first = shape.ancestorsOfType(edge, Part.Face)[0]
    u, v = first.Surface.parameter(FreeCAD.Vector(*point))
    on_first = (
        first.distToShape(Part.Vertex(FreeCAD.Vector(*point)))[0]
        <= 1e-6 * max(shape.BoundBox.DiagonalLength, 1.0)
        and first.normalAt(u, v).dot(FreeCAD.Vector(*normal)) > 1 - 1e-6
    )
    obj.FlipDirection = not on_first
    return obj


def _edge_name(shape, point) -> str:
    """The name ("EdgeN") of the edge of `shape` nearest `point` (a point on it)."""
    vertex = Part.Vertex(FreeCAD.Vector(*point))
    gaps = [edge.distToShape(vertex)[0] for edge in shape.Edges]
    return f"Edge{gaps.index(min(gaps)) + 1}"


def face_frame(feature: Feature) -> Feature:
    """A FACE feature with the sketch plane of its face: at the face's point, along its
    outward normal."""
    import numpy as np

    from ...brep.features import Frame
    from ...brep.geometry import plane_basis

    u, _ = plane_basis(np.asarray(feature.face.normal, float))
    frame = Frame(feature.face.point, tuple(float(x) for x in u), feature.face.normal)
    return replace(feature, frame=frame)


def _face_name(shape, feature: Feature) -> str:
    """The name ("FaceN") of the planar face of `shape` that the step's face reference
    designates: the one through its point whose outward normal is its normal."""
    point = FreeCAD.Vector(*feature.face.point)
    normal = FreeCAD.Vector(*feature.face.normal)
    tol = 1e-6 * max(shape.BoundBox.DiagonalLength, 1.0)
    vertex = Part.Vertex(point)
    for i, face in enumerate(shape.Faces):
        if face.Surface.__class__.__name__ != "Plane" or face.distToShape(vertex)[0] > tol:
            continue
        u, v = face.Surface.parameter(point)
        if face.normalAt(u, v).dot(normal) > 1 - 1e-6:
            return f"Face{i + 1}"
    raise OperationError(f"no planar face through {tuple(point)} with normal {tuple(normal)}")


def _support_property(obj) -> str:
    """FreeCAD 1.0 renamed an attachment's Support to AttachmentSupport."""
    return "AttachmentSupport" if "AttachmentSupport" in obj.PropertiesList else "Support"


def _attach(doc, body, sketch, previous, feature: Feature) -> None:
    """Attach the sketch to the planar face it stands on (FlatFace), else to the Body's
    XY plane, with the offset that puts it exactly on the step's plane."""
    want = placement(feature.frame)
    support = None
    if (
        FOLLOW_FACES
        and previous is not None
        and feature.face is not None
        and not feature.face.surface.curved
    ):
        try:
            support = [(previous, _face_name(previous.Shape, feature))]
        except OperationError:
            support = None
    if support is None:
        xy = next(f for f in body.Origin.OriginFeatures if f.Role == "XY_Plane")
        support = [(xy, "")]
    setattr(sketch, _support_property(sketch), support)
    sketch.MapMode = "FlatFace"
    sketch.AttachmentOffset = FreeCAD.Placement()
    sketch.recompute()
    sketch.AttachmentOffset = sketch.Placement.inverse().multiply(want)


def _keep_solid(
    doc, out: Conversion, plan: Plan, feature: Feature, name: str, reason: str, label: str
):
    """The step's solid as a Part::Feature (the reason in its NotNative property), the
    BaseFeature of a new Body that the later steps build on."""
    solid = doc.addObject("Part::Feature", f"{name}Solid")
    solid.Label = f"{name} (solid)"
    solid.Shape = to_part(plan.solids[feature.step])
    solid.addProperty(
        "App::PropertyString", NOT_NATIVE, "Sketch2CAD", "Why this step is not a PartDesign feature"
    )
    solid.NotNative = reason
    _new_body(doc, out, label, solid)
    doc.recompute()
    return solid
