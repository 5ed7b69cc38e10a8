# SPDX-License-Identifier: LGPL-2.1-or-later
"""Screenshot of the workbench with a multi-step model, for the documentation.

Run inside FreeCAD's GUI on a virtual X screen, from the repository root:

    LANG=C.UTF-8 QTWEBENGINE_DISABLE_SANDBOX=1 xvfb-run -a -s "-screen 0 1600x1000x24" \\
        freecad scripts/screenshot.py

It loads examples/protocols/hammer.json (all four operators) through the Load protocol
command, selects its first Revolution so that the property editor shows its parameters
(in the user's units), and writes the main window to docs/workbench.png (or to
$SKETCH2CAD_SCREENSHOT). With SKETCH2CAD_SCREENSHOT_MODE=sketch it shows a sketch step
instead: a new box, the strokes of a prism on its top face in the Sketch panel,
interpreted by the shipped weights, read as a Boss with the blue preview
(docs/sketch-step.png). FreeCAD exits with status 0 once the file is written, 1
otherwise.
"""

import os
import sys
import traceback

import FreeCAD
import FreeCADGui
import numpy as np
from PySide import QtCore, QtGui

from Sketch2CADWorkbench.freecad_layer.env import ROOT

sys.path.insert(0, os.path.join(ROOT, "scripts"))
from gui_capture import grab, settle

PROTOCOL = os.path.join(ROOT, "examples", "protocols", "hammer.json")
SKETCH = os.environ.get("SKETCH2CAD_SCREENSHOT_MODE") == "sketch"
OUT = os.environ.get(
    "SKETCH2CAD_SCREENSHOT",
    os.path.join(ROOT, "docs", "sketch-step.png" if SKETCH else "workbench.png"),
)
WINDOW = (1500, 900)  # device-independent pixels (Xvfb: 1.04 device pixels each)


def show_model():
    """The hammer's model tree, its last feature shown, a Revolution selected."""
    from Sketch2CADWorkbench.commands.protocol import load_protocol_file
    from Sketch2CADWorkbench.freecad_layer.queries import features

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


def show_sketch_step():
    """A new box and the Sketch panel holding a hand-drawn-looking hexagonal prism on its
    top face (the strokes the data generator would draw, jittered), interpreted."""
    from Sketch2CADWorkbench.brep.protocol import AddSubPrism, FaceRef, Mode
    from Sketch2CADWorkbench.freecad_layer.make.make_model import make_model
    from Sketch2CADWorkbench.freecad_layer.shapes import from_part
    from Sketch2CADWorkbench.freecad_layer.taskpanels.sketch_panel import SketchPanel
    from Sketch2CADWorkbench.sketch.curves import operation_curves

    FreeCADGui.activateWorkbench("Sketch2CADWorkbench")
    doc = FreeCAD.newDocument("Sketch")
    model = make_model(doc)
    view = FreeCADGui.ActiveDocument.ActiveView
    view.setCameraType("Orthographic")
    view.viewIsometric()
    view.fitAll()
    angles = np.radians(np.arange(6) * 60.0)
    hexagon = tuple((float(7 * np.cos(a)), float(7 * np.sin(a)), 10.0) for a in angles)
    op = AddSubPrism(FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0)), hexagon, 12.0, Mode.ADD)
    direction = np.array(view.getViewDirection())
    rng = np.random.default_rng(3)
    panel = SketchPanel(model)
    FreeCADGui.Control.showDialog(panel)
    for curve in operation_curves(from_part(model.Tip.Shape), op, direction):
        wobble = rng.normal(0, 0.25, 3) + np.outer(
            np.sin(np.linspace(0, np.pi, len(curve.points))), rng.normal(0, 0.3, 3)
        )
        panel.capture.strokes.append(list(curve.points + wobble))
    panel.capture.redraw()
    panel.interpret()  # in FreeCAD's default layout: the panel fits the combo view
    if panel.result is None:
        raise RuntimeError(panel.text.toPlainText())


def main():
    code = 0
    try:
        mw = FreeCADGui.getMainWindow()
        mw.showNormal()
        mw.setGeometry(0, 0, *WINDOW)
        settle()
        if SKETCH:
            show_sketch_step()
        else:
            show_model()
            settle()
            FreeCADGui.ActiveDocument.ActiveView.fitAll()
        grab(OUT)
        print(f"screenshot: wrote {OUT}", file=sys.__stdout__)  # 1.0: stdout is the report view
    except Exception:
        traceback.print_exc(file=sys.__stdout__)
        code = 1
    sys.__stdout__.flush()
    os._exit(code)


QtCore.QTimer.singleShot(0, main)
