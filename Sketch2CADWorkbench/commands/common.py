# SPDX-License-Identifier: LGPL-2.1-or-later
"""What the commands share: their resources and the active model (messages and undo
steps: freecad_layer/gui_helpers.py)."""

import FreeCAD
import FreeCADGui

from ..freecad_layer.icons import icon_path
from ..freecad_layer.queries import find_models


def resources(icon: str, menu: str, tip: str, accel: str = "") -> dict:
    """A command's GetResources() dict; `icon` names an SVG in resources/icons."""
    return {"Pixmap": icon_path(icon), "MenuText": menu, "ToolTip": tip, "Accel": accel}


def active_model():
    """The selected model (or the model of a selected feature), else the active document's
    last model, else None."""
    doc = FreeCAD.ActiveDocument
    if doc is None:
        return None
    models = find_models(doc)
    for sel in FreeCADGui.Selection.getSelection():
        for model in models:
            if sel == model or sel in model.Group:
                return model
    return models[-1] if models else None
