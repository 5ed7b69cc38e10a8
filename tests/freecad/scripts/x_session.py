# SPDX-License-Identifier: LGPL-2.1-or-later
"""Inside FreeCAD for test_x_events.py, which drives it from outside with X events: sets
up a model in an isometric view in FreeCAD's default layout (FreeCAD 1.1's: the Tasks
panel floats over the view's right side) or with every panel floating over it
(SKETCH2CAD_OVERLAY=1: FreeCAD 1.1's overlay mode for all), opens the Sketch panel, and
then only reports what a user sees, every 100 ms, to $SKETCH2CAD_TMP/state.json: the
windows' and buttons' places on the screen, the view's camera, the panel's reading and
strokes, the model's features. It sends no event itself: every click, drag and key comes
from outside."""

import json
import os
import sys
import time

sys.path.insert(0, os.path.join(os.environ["SKETCH2CAD_ROOT"], "tests", "freecad", "scripts"))
import FreeCAD
import FreeCADGui
from harness import TMP, say, tested_checkout
from PySide import QtCore, QtGui

from Sketch2CADWorkbench.freecad_layer.taskpanels import sketch_panel

STATE = os.path.join(TMP, "state.json")
PANELS = []  # the Sketch panels opened, the last one current
_init = sketch_panel.SketchPanel.__init__


def _recorded_init(self, *args, **kwargs):
    _init(self, *args, **kwargs)
    PANELS.append(self)


sketch_panel.SketchPanel.__init__ = _recorded_init


def rect(widget) -> list:
    """A widget's place on the screen: [x, y, width, height] in the screen's pixels (Qt's
    are device-independent: scaled by the screen's DPI)."""
    p = widget.mapToGlobal(QtCore.QPoint(0, 0))
    k = widget.devicePixelRatioF()
    return [round(k * v) for v in (p.x(), p.y(), widget.width(), widget.height())]


def buttons() -> list:
    """The visible buttons of the main window: [text, rect, checked]."""
    mw = FreeCADGui.getMainWindow()
    return [
        [b.text().replace("&", ""), rect(b), b.isChecked()]
        for b in mw.findChildren(QtGui.QAbstractButton)
        if b.isVisible() and b.text()
    ]


def overlay_of(widget):
    """The overlay panel (FreeCAD 1.1's Gui::OverlayTabWidget) the widget lies in, if any."""
    w = widget
    while w is not None:
        if "Overlay" in w.metaObject().className():
            return w
        w = w.parentWidget()
    return None


def all_overlaid() -> bool:
    """Every visible docked panel (Model, Tasks...) floats over the 3D view."""
    docks = FreeCADGui.getMainWindow().findChildren(QtGui.QDockWidget)
    return all(overlay_of(d) is not None for d in docks if d.isVisible())


def panel_state() -> dict | None:
    panel = PANELS[-1] if PANELS else None
    if panel is None or panel.closed:
        return None
    form = panel.form
    scrolls = [
        w
        for w in FreeCADGui.getMainWindow().findChildren(QtGui.QScrollArea)
        if w.isAncestorOf(form)
    ]
    overlay = overlay_of(form)
    r = panel.result
    return {
        "form": rect(form),
        "area": rect(scrolls[-1].viewport()) if scrolls else None,
        "hscroll": bool(scrolls and scrolls[-1].horizontalScrollBar().isVisible()),
        "overlay": rect(overlay) if overlay is not None else None,
        "text": panel.text.toPlainText(),
        "strokes": len(panel.capture.strokes),
        "kind": None if r is None else r.op_type.value,
        "doubtful": bool(r is not None and r.doubtful),
        "regularize": rect(panel.regularize),
        "anyway": panel.anyway_button.isVisible(),
    }


def state() -> dict:
    from Sketch2CADWorkbench.freecad_layer.queries import features, find_models
    from Sketch2CADWorkbench.freecad_layer.trackers.view_camera import view_camera

    gui = FreeCADGui.ActiveDocument
    view = gui.ActiveView
    viewport = view.graphicsView().viewport()
    cam = view_camera(view)
    models = find_models(FreeCAD.ActiveDocument)
    screen = QtGui.QApplication.primaryScreen()
    k = screen.devicePixelRatio()
    return {
        "time": time.time(),  # when FreeCAD wrote it: a busy FreeCAD writes none
        "screen": [round(k * screen.geometry().width()), round(k * screen.geometry().height())],
        "window": rect(FreeCADGui.getMainWindow()),
        "viewport": rect(viewport),
        "camera": {
            "center": list(map(float, cam.center)),
            "direction": list(map(float, cam.direction)),
            "up": list(map(float, cam.up)),
            "scale": float(cam.scale),
            "width": cam.width,
            "height": cam.height,
        },
        "features": [[o.Label, o.Shape.Volume, o.isValid()] for m in models for o in features(m)],
        "modified": bool(gui.Modified),
        "panel": panel_state(),
        "buttons": buttons(),
        "overlay_mode": OVERLAY,
        "modal": modal_dialog(),
    }


def modal_dialog() -> str | None:
    """The name of the modal dialog open (it takes every mouse event), or None."""
    w = QtGui.QApplication.activeModalWidget()
    return None if w is None else w.objectName() or w.metaObject().className()


def report() -> None:
    try:
        text = json.dumps(state())
    except Exception as e:  # a state between two events: the next report has it
        text = json.dumps({"error": repr(e)})
    with open(STATE + ".tmp", "w") as f:
        f.write(text)
    os.replace(STATE + ".tmp", STATE)


OVERLAY = False


def main() -> None:
    tested_checkout()
    mw = FreeCADGui.getMainWindow()
    mw.showMaximized()
    FreeCADGui.activateWorkbench("Sketch2CADWorkbench")
    FreeCAD.newDocument("x")
    FreeCADGui.runCommand("Sketch2CAD_NewModel")
    view = FreeCADGui.ActiveDocument.ActiveView
    view.viewIsometric()
    view.fitAll()
    QtCore.QTimer.singleShot(1500, open_panel)  # after FreeCAD 1.1's view animation


def open_panel() -> None:
    """Room above the box for what is drawn on its top (a designer zooms out so), and the
    Sketch panel."""
    global OVERLAY
    camera = FreeCADGui.ActiveDocument.ActiveView.getCameraNode()
    camera.height.setValue(1.8 * camera.height.getValue())
    FreeCADGui.runCommand("Sketch2CAD_Sketch")
    if os.environ.get("SKETCH2CAD_OVERLAY") == "1":
        # FreeCAD 1.1: every docked panel floats over the 3D view (View > Overlay > Toggle
        # overlay for all; it turns them all off when one floats, as the Tasks panel does
        # in 1.1's default layout, so a second toggle turns them all on)
        assert "Std_DockOverlayAll" in FreeCADGui.listCommands(), "no overlay mode"
        for _ in range(2):
            if all_overlaid():
                break
            FreeCADGui.runCommand("Std_DockOverlayAll")
        assert all_overlaid(), "Toggle overlay for all left a docked panel"
        OVERLAY = True
    timer = QtCore.QTimer(FreeCADGui.getMainWindow())
    timer.timeout.connect(report)
    timer.start(100)
    say("X SESSION READY")


QtCore.QTimer.singleShot(500, main)
