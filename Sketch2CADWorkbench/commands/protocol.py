# SPDX-License-Identifier: LGPL-2.1-or-later
"""Protocol files: load one as a model tree, save a model as one, replay a model."""

import time
from pathlib import Path

import FreeCAD
import FreeCADGui
from PySide import QtGui

from ..brep.protocol import ProtocolError, load
from ..freecad_layer.gui_helpers import error, progress, transaction
from ..freecad_layer.queries import (
    failed_features,
    features,
    find_models,
    protocol_from_model,
    refuse_failed_steps,
)
from ..freecad_layer.translate import QT_TRANSLATE_NOOP, translate
from .common import active_model, resources

PROTOCOL_FILTER = "Sketch2CAD protocol (*.json)"
REPLAY_STEP_S = 0.5


class LoadProtocol:
    """Load protocol: a file dialog, then `load_protocol_file`."""

    def GetResources(self):
        return resources(
            "LoadProtocol",
            QT_TRANSLATE_NOOP("Sketch2CAD_LoadProtocol", "Load protocol..."),
            QT_TRANSLATE_NOOP(
                "Sketch2CAD_LoadProtocol", "Build a new model tree from a protocol file (JSON)"
            ),
        )

    def IsActive(self):
        return True

    def Activated(self):
        path, _ = QtGui.QFileDialog.getOpenFileName(
            FreeCADGui.getMainWindow(), "Load protocol", "", PROTOCOL_FILTER
        )
        if path:
            load_protocol_file(path)


def load_protocol_file(path: str):
    """A new model in the active document (or a new one) from a protocol file.

    The protocol is validated and built by the core first, so a bad file or a step that
    cannot be built is reported (naming the field or the step) before any document is
    touched. Building the tree is one undo step.

    Returns:
        The new model, or None after telling the user why not.
    """
    # cadquery on first use, not when the workbench is activated (see freecad_layer/shapes.py)
    from ..brep.faces import OperationError
    from ..brep.operators import replay

    try:
        protocol = load(path)
        with progress(f"Replaying {Path(path).name}", len(protocol.operations)) as advance:
            replay(protocol, on_step=lambda _: advance())
    except (ProtocolError, OperationError) as e:
        error(translate("Sketch2CAD", "Cannot load protocol"), str(e))
        return None
    doc = FreeCAD.ActiveDocument or FreeCAD.newDocument()
    try:
        with transaction(doc, "Load Sketch2CAD protocol"):
            # through the console, as Draft's tools do: the step lands in macros
            FreeCADGui.addModule("Sketch2CADWorkbench.freecad_layer.make.make_model")
            FreeCADGui.addModule("Sketch2CADWorkbench.brep.protocol")
            FreeCADGui.doCommand(
                "Sketch2CADWorkbench.freecad_layer.make.make_model.make_model_from_protocol("
                f"FreeCAD.getDocument({doc.Name!r}), "
                f"Sketch2CADWorkbench.brep.protocol.load({str(path)!r}), "
                f"label={Path(path).stem!r})"
            )
            model = find_models(doc)[-1]
            bad = failed_features(model)
            if bad:
                raise OperationError("; ".join(f"{o.Label}: {o.getStatusString()}" for o in bad))
    except (OperationError, ValueError) as e:
        error(translate("Sketch2CAD", "Cannot build protocol"), f"{path}: {e}")
        return None
    if FreeCAD.GuiUp:
        FreeCADGui.SendMsgToActiveView("ViewFit")
    return model


class SaveProtocol:
    """Save protocol: the selected model's protocol as JSON."""

    def GetResources(self):
        return resources(
            "SaveProtocol",
            QT_TRANSLATE_NOOP("Sketch2CAD_SaveProtocol", "Save protocol..."),
            QT_TRANSLATE_NOOP(
                "Sketch2CAD_SaveProtocol",
                "Save the selected model's steps as a protocol file (JSON)",
            ),
        )

    def IsActive(self):
        return active_model() is not None

    def Activated(self):
        model = active_model()
        path, _ = QtGui.QFileDialog.getSaveFileName(
            FreeCADGui.getMainWindow(), "Save protocol", f"{model.Label}.json", PROTOCOL_FILTER
        )
        if path:
            save_protocol_file(model, path)


def save_protocol_file(model, path: str) -> bool:
    """Write the model's protocol; tell the user and return False when it cannot be."""
    try:
        refuse_failed_steps(model, "saving the protocol")
        protocol_from_model(model).save(path)
    except (ValueError, OSError) as e:
        error(translate("Sketch2CAD", "Cannot save protocol"), f"{model.Label}: {e}")
        return False
    return True


class ReplayProtocol:
    """Replay protocol: `replay_model` on the selected model."""

    def GetResources(self):
        return resources(
            "ReplayProtocol",
            QT_TRANSLATE_NOOP("Sketch2CAD_ReplayProtocol", "Replay protocol"),
            QT_TRANSLATE_NOOP(
                "Sketch2CAD_ReplayProtocol",
                "Rebuild the selected model step by step, showing each step's result",
            ),
        )

    def IsActive(self):
        return active_model() is not None

    def Activated(self):
        replay_model(active_model())


def replay_model(model, step_s: float = REPLAY_STEP_S) -> bool:
    """Recompute the model's features one by one, showing each result for `step_s` seconds.

    Stops at a step that fails (it stays in error state, shown) and tells the user why.

    Returns:
        True when every step was rebuilt.
    """
    chain = features(model)
    for obj in chain:
        obj.ViewObject.Visibility = False
    failed = None
    with progress(f"Replaying {model.Label}", len(chain)) as advance:
        for i, obj in enumerate(chain):
            obj.touch()
            built = obj.recompute()
            if i:
                chain[i - 1].ViewObject.Visibility = False
            obj.ViewObject.Visibility = True
            advance()
            FreeCADGui.updateGui()
            if not built:
                failed = f"step {i} ({obj.Label}): {obj.getStatusString()}"
                break
            time.sleep(step_s)
    if failed:  # told once the progress bar is gone
        error(translate("Sketch2CAD", "Replay stopped"), failed)
        return False
    return True
