# SPDX-License-Identifier: LGPL-2.1-or-later
"""What the commands share: their resources, the active model, transactions, messages."""
from contextlib import contextmanager

import FreeCAD
import FreeCADGui
from PySide import QtGui

from ..freecad_layer.icons import icon_path
from ..freecad_layer.make.make_model import find_models


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


def error(title: str, message: str) -> None:
    """Tell the user what went wrong: report view and a message box."""
    FreeCAD.Console.PrintError(f"Sketch2CAD: {message}\n")
    QtGui.QMessageBox.critical(FreeCADGui.getMainWindow(), title, message)


@contextmanager
def transaction(doc, name: str):
    """One undo step; aborted, leaving the document as it was, when the body raises."""
    doc.openTransaction(name)
    try:
        yield
    except Exception:
        doc.abortTransaction()
        doc.recompute()
        raise
    doc.commitTransaction()
