# SPDX-License-Identifier: LGPL-2.1-or-later
"""Export STEP: the selected model's final solid."""

import FreeCADGui
from PySide import QtGui

from ..freecad_layer.export import export_step
from ..freecad_layer.gui_helpers import error
from ..freecad_layer.translate import QT_TRANSLATE_NOOP, translate
from .common import active_model, resources


class ExportStep:
    """Export STEP: the selected model's final solid, through FreeCAD's STEP writer."""

    def GetResources(self):
        return resources(
            "ExportStep",
            QT_TRANSLATE_NOOP("Sketch2CAD_ExportStep", "Export STEP..."),
            QT_TRANSLATE_NOOP(
                "Sketch2CAD_ExportStep",
                "Write the selected model's final solid as a STEP file (AP214, mm)",
            ),
        )

    def IsActive(self):
        return active_model() is not None

    def Activated(self):
        model = active_model()
        path, _ = QtGui.QFileDialog.getSaveFileName(
            FreeCADGui.getMainWindow(), "Export STEP", f"{model.Label}.step", "STEP (*.step *.stp)"
        )
        if path:
            export_model_step(model, path)


def export_model_step(model, path: str) -> bool:
    """Export, telling the user and returning False when it fails."""
    try:
        export_step(model, path)
    except (ValueError, OSError) as e:
        error(translate("Sketch2CAD", "Cannot export STEP"), str(e))
        return False
    return True
