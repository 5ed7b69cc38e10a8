# SPDX-License-Identifier: LGPL-2.1-or-later
"""What the commands and the task panels share: telling the user, showing progress, and one
undo step."""

from collections.abc import Callable, Iterator
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


@contextmanager
def progress(text: str, steps: int) -> Iterator[Callable[[], None]]:
    """FreeCAD's progress indicator over `steps` steps (a progress bar in the status bar
    of the GUI, percentages in the console): yields the call that advances it one step,
    and ends it however the body ends."""
    indicator = FreeCAD.Base.ProgressIndicator()
    indicator.start(text, steps)
    try:
        yield indicator.next
    finally:
        indicator.stop()
