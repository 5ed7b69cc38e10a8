# SPDX-License-Identifier: LGPL-2.1-or-later
"""Sketch: strokes over the 3D view -> the interpreted operation -> a new feature (the task
panel: freecad_layer/taskpanels/sketch_panel.py)."""

import FreeCAD
import FreeCADGui

from ..freecad_layer.taskpanels.sketch_panel import SketchPanel
from ..freecad_layer.translate import QT_TRANSLATE_NOOP
from .common import active_model, resources


class Sketch:
    def GetResources(self):
        return resources(
            "Sketch",
            QT_TRANSLATE_NOOP("Sketch2CAD_Sketch", "Sketch an operation"),
            QT_TRANSLATE_NOOP(
                "Sketch2CAD_Sketch",
                "Draw strokes over the model (left drag); "
                "Enter reads them as a pad or pocket, bevel, boss or hole, or "
                "revolution or groove; Esc cancels",
            ),
            "S, S",
        )

    def IsActive(self):
        return active_model() is not None and FreeCADGui.Control.activeDialog() is False

    def Activated(self):
        view = FreeCADGui.ActiveDocument.ActiveView
        if view.getCameraType() != "Orthographic":
            # sketches are read in parallel views (the paper's pipeline); say so and switch
            view.setCameraType("Orthographic")
            FreeCAD.Console.PrintMessage(
                "Sketch2CAD: the view was switched to orthographic: "
                "sketches are read in parallel views\n"
            )
        FreeCADGui.Selection.clearSelection()  # selection green is not the preview's colour
        FreeCADGui.Control.showDialog(SketchPanel(active_model()))
