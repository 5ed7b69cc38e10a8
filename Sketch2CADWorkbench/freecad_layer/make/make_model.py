# SPDX-License-Identifier: LGPL-2.1-or-later
"""Building Sketch2CAD models in a FreeCAD document (reading them back: ../queries.py).

These work with or without the GUI (commands and tests share them); view providers are
attached only when FreeCAD.GuiUp.
"""

import FreeCAD

from ...brep.protocol import Box, Operation, Protocol, per_operator
from ..objects.bevel import BevelFeature
from ..objects.box import BoxFeature
from ..objects.extrude import ExtrudeFeature
from ..objects.model import ModelFeature
from ..objects.prism import PrismFeature
from ..objects.shell import ShellFeature
from ..objects.sweep import SweepFeature

FEATURE_OF_OPERATION = per_operator(
    {
        cls.OPERATION.type: cls
        for cls in (ExtrudeFeature, BevelFeature, PrismFeature, SweepFeature, ShellFeature)
    },
    "FEATURE_OF_OPERATION",
)
DEFAULT_BOX = Box((40.0, 30.0, 20.0))


def _view(obj) -> None:
    if FreeCAD.GuiUp:
        from ..viewproviders.view_feature import ViewProviderSketch2CAD

        ViewProviderSketch2CAD(obj.ViewObject)


def make_model(doc, box: Box = DEFAULT_BOX, label: str = "Model"):
    """A new model: a group holding a base box, recomputed.

    Args:
        doc: the FreeCAD document to add it to.
        box: the base box (size in mm, centred on the origin).
        label: the model's label in the tree.

    Returns:
        The model (App::DocumentObjectGroupPython); its Tip is the box feature.
    """
    model = doc.addObject("App::DocumentObjectGroupPython", "Sketch2CADModel")
    ModelFeature(model)
    model.Label = label
    _view(model)
    base = doc.addObject("Part::FeaturePython", "Box")
    BoxFeature(base)
    base.Proxy.set_box(base, box)
    _view(base)
    model.addObject(base)
    model.Tip = base
    doc.recompute()
    return model


def _new_feature(doc, op: Operation, sketch: str):
    cls = FEATURE_OF_OPERATION[op.type]
    obj = doc.addObject("Part::FeaturePython", cls.kind_of(op))  # Pad, Hole...
    cls(obj)
    obj.Proxy.set_operation(obj, op)
    obj.SketchStep = sketch
    _view(obj)
    return obj


def add_operation(model, op: Operation, sketch: str = ""):
    """Append a feature for `op` after the model's Tip; it becomes the new Tip.

    The previous Tip is hidden, as PartDesign does, so the view shows the result. The
    document is not recomputed here (callers append several steps, then recompute once).

    Args:
        model: the model (see make_model).
        op: the operation.
        sketch: the sketch it was read from, as a step of a session file in JSON
            (`inference.session.step_to_dict`), kept so that it can be read again;
            "" when there is none (protocols).

    Returns:
        The new Part::FeaturePython, named and labelled as a FreeCAD user reads it (a
        Pad, Pocket, Boss, Hole, Revolution, Groove or Bevel).
    """
    obj = _new_feature(model.Document, op, sketch)
    obj.Base = model.Tip
    model.addObject(obj)
    if FreeCAD.GuiUp:
        model.Tip.ViewObject.Visibility = False
    model.Tip = obj
    return obj


def replace_operation(obj, op: Operation, sketch: str = ""):
    """Make the feature `obj` stand for `op` (read again from its sketch): its values
    change in place when `op` is of the same operator; else a feature of the new operator
    takes its place in the model (the later steps are rebased on it) and `obj` is removed.
    The document is not recomputed here.

    Returns:
        The feature that now stands for `op`.
    """
    if type(op) is obj.Proxy.OPERATION:
        obj.Proxy.set_operation(obj, op)
        obj.Proxy.update_kind(obj)
        obj.SketchStep = sketch
        return obj
    model = next(m for m in obj.InList if obj in getattr(m, "Group", []))
    new = _new_feature(obj.Document, op, sketch)
    new.Base = obj.Base
    for later in obj.InList:
        if getattr(later, "Base", None) == obj:
            later.Base = new
    model.Group = [new if o == obj else o for o in model.Group]
    if model.Tip == obj:
        model.Tip = new
    if FreeCAD.GuiUp:
        new.ViewObject.Visibility = obj.ViewObject.Visibility
    obj.Document.removeObject(obj.Name)
    return new


def make_model_from_protocol(doc, protocol: Protocol, label: str = "Model"):
    """A model tree equal to `protocol`: the box and one feature per operation, recomputed.

    A step that cannot be built is left in FreeCAD's error state (see `queries.failed_features`).
    """
    model = make_model(doc, protocol.base, label)
    for op in protocol.operations:
        add_operation(model, op)
    doc.recompute()
    return model
