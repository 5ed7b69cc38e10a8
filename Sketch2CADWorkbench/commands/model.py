# SPDX-License-Identifier: LGPL-2.1-or-later
"""New model: a base box to sketch on."""
import FreeCAD
import FreeCADGui

from ..freecad_layer.make.make_model import features, make_model
from .common import resources, transaction


class NewModel:
    """New model: a base box of the default size, shown in an orthographic isometric view."""

    def GetResources(self):
        return resources("Model", "New model",
                         "Start a Sketch2CAD model from a box; select the Box to edit its "
                         "size in the property editor", "S, N")

    def IsActive(self):
        return True

    def Activated(self):
        doc = FreeCAD.ActiveDocument or FreeCAD.newDocument()
        with transaction(doc, "New Sketch2CAD model"):
            model = make_model(doc)
        FreeCADGui.Selection.clearSelection()
        FreeCADGui.Selection.addSelection(features(model)[0])
        view = FreeCADGui.ActiveDocument.ActiveView
        view.setCameraType("Orthographic")  # the paper's sketches are drawn in parallel views
        view.viewIsometric()
        view.fitAll()
