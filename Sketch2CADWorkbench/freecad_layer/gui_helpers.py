# SPDX-License-Identifier: LGPL-2.1-or-later
"""What the commands and the task panels share: telling the user, and one undo step."""

from contextlib import contextmanager

import FreeCAD
import FreeCADGui
from PySide import QtGui


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
