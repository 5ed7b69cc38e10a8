# SPDX-License-Identifier: LGPL-2.1-or-later
"""Reading Sketch2CAD models in a FreeCAD document: their features, their protocol, their
errors, the models of a document. With or without the GUI."""

from ..brep.protocol import Protocol
from .objects.model import ModelFeature


def features(model) -> list:
    """The model's features in order: the box, then each operation (following Base links
    back from the Tip)."""
    chain = []
    obj = model.Tip
    while obj is not None:
        chain.append(obj)
        obj = getattr(obj, "Base", None)
    return chain[::-1]


def protocol_from_model(model) -> Protocol:
    """The protocol of a model tree, from its features' current property values."""
    box, *ops = features(model)
    return Protocol(box.Proxy.box(box), tuple(obj.Proxy.operation(obj) for obj in ops))


def failed_features(model) -> list:
    """The model's features that are in FreeCAD's error state, in order."""
    return [obj for obj in features(model) if not obj.isValid()]


def find_models(doc) -> list:
    """The document's Sketch2CAD models, in creation order."""
    return [
        o
        for o in doc.Objects
        if getattr(getattr(o, "Proxy", None), "TYPE", "") == ModelFeature.TYPE
    ]


def refuse_failed_steps(model, doing: str) -> None:
    """Raise ValueError naming the model's first step in error, if any: the later steps'
    solids would be those from before the edit that broke it.

    Args:
        doing: what is refused, for the message ("exporting", "saving the protocol").
    """
    bad = failed_features(model)
    if bad:
        status = bad[0].getStatusString()
        raise ValueError(
            f"{model.Label}: step {bad[0].Label} failed to build ({status}); fix it before {doing}"
        )
