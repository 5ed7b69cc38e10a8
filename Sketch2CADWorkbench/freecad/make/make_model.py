# SPDX-License-Identifier: LGPL-2.1-or-later
"""Building Sketch2CAD models in a FreeCAD document, and converting them to protocols.

These work with or without the GUI; view providers are attached only when FreeCAD.GuiUp.
"""
import FreeCAD

from ...brep.protocol import AddSubPrism, Bevel, Box, Extrude, Operation, Protocol, Sweep
from ..objects.bevel import BevelFeature
from ..objects.box import BoxFeature
from ..objects.extrude import ExtrudeFeature
from ..objects.model import ModelFeature
from ..objects.prism import PrismFeature
from ..objects.sweep import SweepFeature

FEATURE_OF_OPERATION = {Extrude: ExtrudeFeature, Bevel: BevelFeature,
                        AddSubPrism: PrismFeature, Sweep: SweepFeature}
LABEL_OF_FEATURE = {ExtrudeFeature: "Extrude", BevelFeature: "Bevel",
                    PrismFeature: "Prism", SweepFeature: "Sweep"}


def _view(obj) -> None:
    if FreeCAD.GuiUp:
        from ..viewproviders.view_feature import ViewProviderSketch2CAD
        ViewProviderSketch2CAD(obj.ViewObject)


def make_model(doc, box: Box = Box((40.0, 30.0, 20.0)), label: str = "Model"):
    """A new model: a group holding a base box of `box.size` mm."""
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


def add_operation(model, op: Operation):
    """Append an operation feature after the model's Tip; it becomes the new Tip.

    The previous Tip is hidden, as PartDesign does, so the view shows the result.
    """
    doc = model.Document
    cls = FEATURE_OF_OPERATION[type(op)]
    obj = doc.addObject("Part::FeaturePython", LABEL_OF_FEATURE[cls])
    cls(obj)
    obj.Proxy.set_operation(obj, op)
    obj.Base = model.Tip
    _view(obj)
    model.addObject(obj)
    if FreeCAD.GuiUp and model.Tip is not None:
        model.Tip.ViewObject.Visibility = False
    model.Tip = obj
    return obj


def features(model) -> list:
    """The model's features in order: the box, then each operation (following Base links)."""
    chain = []
    obj = model.Tip
    while obj is not None:
        chain.append(obj)
        obj = getattr(obj, "Base", None)
    return chain[::-1]


def make_model_from_protocol(doc, protocol: Protocol, label: str = "Model"):
    """A model tree equal to a protocol: the box and one feature per operation."""
    model = make_model(doc, protocol.base, label)
    for op in protocol.operations:
        add_operation(model, op)
    doc.recompute()
    return model


def protocol_from_model(model) -> Protocol:
    """The protocol of a model tree (its current property values)."""
    chain = features(model)
    box = chain[0].Proxy.box(chain[0])
    return Protocol(box, tuple(obj.Proxy.operation(obj) for obj in chain[1:]))


def model_shape(model):
    """The model's final solid (its Tip's shape)."""
    return model.Tip.Shape


def find_models(doc) -> list:
    return [o for o in doc.Objects
            if getattr(getattr(o, "Proxy", None), "TYPE", "") == ModelFeature.TYPE]
