# SPDX-License-Identifier: LGPL-2.1-or-later
"""What the documentation's screenshot scripts share, inside FreeCAD's GUI: letting the
GUI settle, and capturing the main window as the X screen shows it."""

import os
import time

import FreeCADGui
from PySide import QtGui


def settle(seconds: float = 1.0) -> None:
    """Process events for a while: FreeCAD 1.1 animates view changes."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        QtGui.QApplication.processEvents()
        time.sleep(0.02)


def grab(path: str) -> None:
    """The main window as shown on the X screen (the 3D view is drawn with OpenGL, which
    QWidget.grab does not capture)."""
    settle()
    geometry = FreeCADGui.getMainWindow().frameGeometry()
    image = QtGui.QGuiApplication.primaryScreen().grabWindow(
        0, geometry.x(), geometry.y(), geometry.width(), geometry.height()
    )
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    if not image.save(path):
        raise OSError(f"{path}: cannot write the screenshot")
