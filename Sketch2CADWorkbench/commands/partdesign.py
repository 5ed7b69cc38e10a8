# SPDX-License-Identifier: LGPL-2.1-or-later
"""Convert to PartDesign Body: the selected model as FreeCAD's own features."""

import FreeCAD
import FreeCADGui

from ..freecad_layer.gui_helpers import error, transaction
from ..freecad_layer.queries import refuse_failed_steps
from ..freecad_layer.translate import QT_TRANSLATE_NOOP, translate
from .common import active_model, resources


class ConvertToPartDesign:
    """Convert to PartDesign Body: `convert_model` on the selected model, one undo step."""

    def GetResources(self):
        return resources(
            "ConvertToPartDesign",
            QT_TRANSLATE_NOOP("Sketch2CAD_ConvertToPartDesign", "Convert to PartDesign Body"),
            QT_TRANSLATE_NOOP(
                "Sketch2CAD_ConvertToPartDesign",
                "Rebuild the selected model as a PartDesign Body of native features "
                "(fully constrained sketches, Pad, Pocket, Revolution, Groove) that opens and "
                "recomputes without this workbench",
            ),
        )

    def IsActive(self):
        return active_model() is not None

    def Activated(self):
        convert_selected(active_model())


def convert_selected(model):
    """Convert `model` through the console (the step lands in macros); tell the user about
    steps kept as solids. Returns the conversion, or None after saying why not."""
    from ..brep.faces import OperationError
    from ..freecad_layer.partdesign.convert import LAST

    doc = model.Document
    try:
        refuse_failed_steps(model, "converting it")
        with transaction(doc, "Convert to PartDesign Body"):
            FreeCADGui.addModule("Sketch2CADWorkbench.freecad_layer.partdesign.convert")
            FreeCADGui.doCommand(
                "Sketch2CADWorkbench.freecad_layer.partdesign.convert.convert_model("
                f"FreeCAD.getDocument({doc.Name!r}).getObject({model.Name!r}))"
            )
    except (OperationError, ValueError) as e:
        error(translate("Sketch2CAD", "Cannot convert to PartDesign"), f"{model.Label}: {e}")
        return None
    conversion = LAST[doc.Name]
    for step in conversion.steps:
        if not step.native:
            FreeCAD.Console.PrintWarning(
                f"{conversion.body.Label}: step {step.step} ({step.label}) kept as a solid: "
                f"{step.reason}\n"
            )
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(conversion.body)
    return conversion
