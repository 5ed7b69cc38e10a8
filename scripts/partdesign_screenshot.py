# SPDX-License-Identifier: LGPL-2.1-or-later
"""Screenshots of a model converted into a PartDesign Body, for the documentation; also
the GUI check of the Convert to PartDesign Body command (tests/freecad/test_partdesign.py).

Run inside FreeCAD's GUI on a virtual X screen, from the repository root:

    LANG=C.UTF-8 QTWEBENGINE_DISABLE_SANDBOX=1 xvfb-run -a -s "-screen 0 1600x1000x24" \\
        freecad scripts/partdesign_screenshot.py

This checkout is imported whatever FreeCAD's Mod folder links to, and its command is
registered. It loads examples/protocols/hammer.json as a model, selects it, runs
Sketch2CAD_ConvertToPartDesign, and writes the main window with the Body's tree to
docs/partdesign-tree.png, then with a sketch open in the Sketcher (its named
constraints listed) to docs/partdesign-sketch.png (or both into $SKETCH2CAD_SCREENSHOT_DIR).
Prints "CHECK PASSED convert_command" when the command made a Body of native features
matching the model; FreeCAD exits 0 once both files are written, 1 otherwise.
"""

import os
import sys
import traceback

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [ROOT, os.path.join(ROOT, "scripts")]
for _name in [m for m in sys.modules if m.split(".")[0] == "Sketch2CADWorkbench"]:
    del sys.modules[_name]  # the Mod folder's workbench may be another checkout

import FreeCAD  # noqa: E402
import FreeCADGui  # noqa: E402
from gui_capture import grab, settle  # noqa: E402
from PySide import QtCore, QtGui  # noqa: E402

OUT = os.environ.get("SKETCH2CAD_SCREENSHOT_DIR", os.path.join(ROOT, "docs"))
WINDOW = (1500, 900)


def say(line: str) -> None:
    print(f"\n{line}", file=sys.__stdout__, flush=True)


def wide_combo_view(tab: str) -> None:
    """The combo view wide enough to read, showing its `tab` ("Model" or "Tasks")."""
    window = FreeCADGui.getMainWindow()
    for dock in window.findChildren(QtGui.QDockWidget):
        if dock.objectName() == "Combo View":
            window.resizeDocks([dock], [430], QtCore.Qt.Horizontal)
            for tabs in dock.findChildren(QtGui.QTabWidget):
                for i in range(tabs.count()):
                    if tabs.tabText(i) == tab:
                        tabs.setCurrentIndex(i)


def show_named_constraints() -> None:
    """The Sketcher panel's constraint list filtered to the named ones (the dimensions)."""
    for box in FreeCADGui.getMainWindow().findChildren(QtGui.QComboBox):
        k = box.findText("Named")
        if k >= 0:
            box.setCurrentIndex(k)


def expand_tree(names) -> None:
    """Expand the tree items whose text is one of `names` (the Bodies)."""
    for tree in FreeCADGui.getMainWindow().findChildren(QtGui.QTreeWidget):
        for item in tree.findItems("", QtCore.Qt.MatchContains | QtCore.Qt.MatchRecursive):
            if item.text(0) in names:
                item.setExpanded(True)


def main() -> int:
    from Sketch2CADWorkbench.freecad_layer import env

    env.bootstrap()
    from Sketch2CADWorkbench.brep.operators import build
    from Sketch2CADWorkbench.brep.protocol import load
    from Sketch2CADWorkbench.commands.partdesign import ConvertToPartDesign
    from Sketch2CADWorkbench.freecad_layer.make.make_model import make_model_from_protocol
    from Sketch2CADWorkbench.freecad_layer.partdesign.convert import LAST

    window = FreeCADGui.getMainWindow()
    window.showNormal()
    window.setGeometry(0, 0, *WINDOW)
    settle()
    FreeCADGui.activateWorkbench("PartDesignWorkbench")
    protocol = load(os.path.join(ROOT, "examples", "protocols", "hammer.json"))
    doc = FreeCAD.newDocument("Hammer")
    model = make_model_from_protocol(doc, protocol, "Hammer")
    FreeCADGui.addCommand("Sketch2CAD_ConvertToPartDesign", ConvertToPartDesign())
    FreeCADGui.Selection.addSelection(model)
    FreeCADGui.runCommand("Sketch2CAD_ConvertToPartDesign")
    conversion = LAST[doc.Name]
    body = conversion.body
    core = build(protocol)
    assert all(s.native for s in conversion.steps), conversion.steps
    assert abs(body.Shape.Volume - core.Volume()) <= 1e-6 * core.Volume()
    assert not model.ViewObject.Visibility and body.ViewObject.Visibility
    say("CHECK PASSED convert_command")
    FreeCADGui.SendMsgToActiveView("ViewFit")
    FreeCADGui.ActiveDocument.ActiveView.viewIsometric()
    FreeCADGui.SendMsgToActiveView("ViewFit")
    wide_combo_view("Model")
    expand_tree({body.Label})
    FreeCADGui.Selection.clearSelection()
    sweep = next(s for s in conversion.steps if s.label == "Revolution")
    FreeCADGui.Selection.addSelection(doc.getObject(sweep.sketch))
    settle(2.0)
    os.makedirs(OUT, exist_ok=True)
    grab(os.path.join(OUT, "partdesign-tree.png"))
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.ActiveDocument.setEdit(doc.getObject(sweep.sketch))
    settle(2.0)
    wide_combo_view("Tasks")
    show_named_constraints()
    FreeCADGui.SendMsgToActiveView("ViewFit")
    grab(os.path.join(OUT, "partdesign-sketch.png"))
    return 0


def run() -> None:
    try:
        code = main()
    except Exception:
        traceback.print_exc(file=sys.__stdout__)
        code = 1
    sys.__stdout__.flush()
    os._exit(code)


QtCore.QTimer.singleShot(0, run)
