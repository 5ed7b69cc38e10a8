# SPDX-License-Identifier: LGPL-2.1-or-later
"""New model: a base box to sketch on."""

import FreeCAD
import FreeCADGui

from ..freecad_layer.gui_helpers import transaction
from ..freecad_layer.queries import features, find_models
from ..freecad_layer.translate import QT_TRANSLATE_NOOP
from .common import resources


class NewModel:
    """New model: a base box of the default size, shown in an orthographic isometric view."""

    def GetResources(self):
        return resources(
            "Model",
            QT_TRANSLATE_NOOP("Sketch2CAD_NewModel", "New model"),
            QT_TRANSLATE_NOOP(
                "Sketch2CAD_NewModel",
                "Start a Sketch2CAD model from a box; "
                "select the Box to edit its size in the property editor",
            ),
            "S, N",
        )

    def IsActive(self):
        return True

    def Activated(self):
        doc = FreeCAD.ActiveDocument or FreeCAD.newDocument()
        with transaction(doc, "New Sketch2CAD model"):
            # through the console, as Draft's tools do: the step lands in macros
            FreeCADGui.addModule("Sketch2CADWorkbench.freecad_layer.make.make_model")
            FreeCADGui.doCommand(
                "Sketch2CADWorkbench.freecad_layer.make.make_model.make_model("
                f"FreeCAD.getDocument({doc.Name!r}))"
            )
            model = find_models(doc)[-1]
        FreeCADGui.Selection.clearSelection()
        FreeCADGui.Selection.addSelection(features(model)[0])
        view = FreeCADGui.ActiveDocument.ActiveView
        view.setCameraType("Orthographic")  # the paper's sketches are drawn in parallel views
        view.viewIsometric()
        view.fitAll()
