# SPDX-License-Identifier: LGPL-2.1-or-later
"""Screenshot of the workbench with a multi-step model, for the documentation.

Run inside FreeCAD's GUI on a virtual X screen, from the repository root:

    LANG=C.UTF-8 QTWEBENGINE_DISABLE_SANDBOX=1 xvfb-run -a -s "-screen 0 1600x1000x24" \\
        freecad scripts/screenshot.py

It loads examples/protocols/hammer.json (all four operators) through the Load protocol
command, selects a sweep so that the property editor shows its parameters, and writes
the main window to docs/workbench.png (or to $SKETCH2CAD_SCREENSHOT). FreeCAD exits with
status 0 once the file is written, 1 otherwise.
"""
import os
import sys
import traceback

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from Sketch2CADWorkbench.freecad_layer.env import ROOT

PROTOCOL = os.path.join(ROOT, "examples", "protocols", "hammer.json")
OUT = os.environ.get("SKETCH2CAD_SCREENSHOT", os.path.join(ROOT, "docs", "workbench.png"))
WINDOW = (1500, 900)  # device-independent pixels (Xvfb: 1.04 device pixels each)


def settle() -> None:
    for _ in range(5):
        QtGui.QApplication.processEvents()


def show_model():
    """The hammer's model tree, its last feature shown, a sweep selected."""
    from Sketch2CADWorkbench.commands.protocol import load_protocol_file
    from Sketch2CADWorkbench.freecad_layer.make.make_model import features
    FreeCADGui.activateWorkbench("Sketch2CADWorkbench")
    FreeCAD.newDocument("Hammer")
    model = load_protocol_file(PROTOCOL)
    if model is None:
        raise RuntimeError(f"{PROTOCOL} did not load")
    view = FreeCADGui.ActiveDocument.ActiveView
    view.setCameraType("Orthographic")
    view.viewIsometric()
    view.fitAll()
    sweep = next(o for o in features(model) if o.Proxy.TYPE == "Sketch2CAD::Sweep")
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(sweep)
    tree = FreeCADGui.getMainWindow().findChild(QtGui.QTreeWidget)
    if tree is not None:
        tree.expandAll()


def grab(path: str) -> None:
    """The main window as shown on the X screen (the 3D view is drawn with OpenGL, which
    QWidget.grab does not capture)."""
    mw = FreeCADGui.getMainWindow()
    settle()
    geometry = mw.frameGeometry()
    image = QtGui.QGuiApplication.primaryScreen().grabWindow(
        0, geometry.x(), geometry.y(), geometry.width(), geometry.height())
    os.makedirs(os.path.dirname(path), exist_ok=True)
    if not image.save(path):
        raise OSError(f"{path}: cannot write the screenshot")


def main():
    code = 0
    try:
        mw = FreeCADGui.getMainWindow()
        mw.showNormal()
        mw.setGeometry(0, 0, *WINDOW)
        settle()
        show_model()
        settle()
        FreeCADGui.ActiveDocument.ActiveView.fitAll()
        grab(OUT)
        print(f"screenshot: wrote {OUT}")
    except Exception:
        traceback.print_exc()
        code = 1
    sys.stdout.flush()
    os._exit(code)


QtCore.QTimer.singleShot(0, main)
