# SPDX-License-Identifier: LGPL-2.1-or-later
"""GUI checks of waiting and mouse capture, run by test_responsiveness.py in FreeCAD on a
virtual X screen: the first activation of the workbench imports neither cadquery nor
torch, the networks load in the background (said in the status bar and the Sketch panel)
and an interpret waits for that load instead of starting a second one; every mouse move
of a stroke reaches the capture while the view redraws.

Lines "FIGURE <name> <value>" report what was measured; no check asserts a duration.
"""

import math
import os
import sys
import threading
import time

sys.path.insert(0, os.path.join(os.environ["SKETCH2CAD_ROOT"], "tests", "freecad", "scripts"))
import FreeCAD
import FreeCADGui
import numpy as np
from harness import check, finish, run_checks, say, send_drag, tested_checkout
from PySide import QtCore, QtGui

from Sketch2CADWorkbench.freecad_layer import networks

HEAVY = ("cadquery", "OCP", "torch", "vtkmodules")
LOADS = []  # one entry per call of networks._load
GATE = threading.Event()  # the background load returns only once this is set
AT_START = {}  # what was imported when the activation started the load
ACTIVATED = []  # when the first activation returned (time.perf_counter)


def app():
    return QtGui.QApplication.instance()


def turn(n: int = 3) -> None:
    for _ in range(n):
        app().processEvents()


def _gated_load(real=networks._load):
    p = real()
    LOADS.append(p)
    GATE.wait(120)  # the checks decide when the load ends (never later than 2 minutes)
    return p


def _recording_start(real=networks.start_loading):
    AT_START["heavy"] = [m for m in HEAVY if m in sys.modules]
    return real()


networks._load = _gated_load
networks.start_loading = _recording_start


def status_label():
    return FreeCADGui.getMainWindow().findChild(QtGui.QLabel, "Sketch2CADNetworksStatus")


@check
def first_activation_imports_no_cadquery_and_starts_the_background_load():
    tested_checkout()
    assert not [m for m in HEAVY if m in sys.modules], [m for m in HEAVY if m in sys.modules]
    start = time.perf_counter()
    FreeCADGui.activateWorkbench("Sketch2CADWorkbench")
    seconds = time.perf_counter() - start
    say(f"FIGURE first_activation_s {seconds:.2f}")
    assert FreeCADGui.activeWorkbench().name() == "Sketch2CADWorkbench"
    turn()  # the load starts once the switch is done
    assert AT_START["heavy"] == [], AT_START  # the commands are in, the heavy modules not
    assert networks.loading()
    assert "loading networks" in status_label().text(), status_label().text()
    FreeCADGui.activateWorkbench("PartWorkbench")  # switching back and forth: one load
    FreeCADGui.activateWorkbench("Sketch2CADWorkbench")
    turn()
    assert (
        len(FreeCADGui.getMainWindow().findChildren(QtGui.QLabel, "Sketch2CADNetworksStatus")) == 1
    )
    ACTIVATED.append(time.perf_counter())


@check
def the_gui_keeps_running_while_the_networks_load():
    """Turns of the event loop every 10 ms from the first activation until the real load
    is done: the longest gap is how long the GUI froze (the GIL held by an import in the
    thread)."""
    start = last = ACTIVATED[0]
    gaps = []
    while not LOADS and time.perf_counter() - start < 300:
        app().processEvents()
        time.sleep(0.01)
        now = time.perf_counter()
        gaps.append(now - last)
        last = now
    assert LOADS, "the networks did not load within 5 minutes"
    gaps.sort()
    say(f"FIGURE background_load_s {time.perf_counter() - start:.1f}")
    say(f"FIGURE longest_gui_stall_while_loading_s {gaps[-1]:.2f}")
    say(f"FIGURE event_loop_turns_while_loading {len(gaps)}")
    assert len(gaps) > 1


@check
def the_sketch_panel_says_the_networks_load_and_interpret_waits_for_them():
    from Sketch2CADWorkbench.freecad_layer.queries import find_models
    from Sketch2CADWorkbench.freecad_layer.taskpanels.sketch_panel import SketchPanel
    from Sketch2CADWorkbench.freecad_layer.trackers.view_camera import view_camera

    FreeCAD.newDocument("waiting")
    FreeCADGui.runCommand("Sketch2CAD_NewModel")
    turn()
    (model,) = find_models(FreeCAD.ActiveDocument)
    view = FreeCADGui.ActiveDocument.ActiveView
    view.viewIsometric()
    view.fitAll()
    turn(10)
    assert networks.loading()  # held at the gate
    panel = SketchPanel(model)
    FreeCADGui.Control.showDialog(panel)
    turn()
    assert panel.text.toPlainText().startswith("Loading networks"), panel.text.toPlainText()
    viewport = view.graphicsView().viewport()
    cam = view_camera(view)
    bb = model.Tip.Shape.BoundBox
    top = np.array(
        [
            [bb.XMin, bb.YMin, bb.ZMax],
            [bb.XMax, bb.YMin, bb.ZMax],
            [bb.XMax, bb.YMax, bb.ZMax],
            [bb.XMin, bb.YMax, bb.ZMax],
        ]
    )
    up = top + [0, 0, 0.5 * bb.ZLength]
    for a, b in [(up[i], up[(i + 1) % 4]) for i in range(4)] + list(zip(top, up, strict=False)):
        send_drag(viewport, cam.project(np.linspace(a, b, 12))[0])
        turn()
    threading.Timer(1.0, GATE.set).start()  # the load ends while interpret waits for it
    panel.interpret()
    try:
        assert len(LOADS) == 1, LOADS  # waited for the background load, loaded nothing twice
        assert panel.result is not None, panel.text.toPlainText()
        assert panel.result.op_type.value == "extrude", panel.text.toPlainText()
        # the session's first reading, once the networks are in (the pipeline's own clock)
        say(f"FIGURE first_interpret_ms {panel.result.timings_ms['total']:.0f}")
        assert networks.predictor() is LOADS[0]
        turn()
        time.sleep(2 * networks.POLL_MS / 1000)
        turn()
        assert "networks ready" in status_label().text(), status_label().text()
    finally:
        panel.reject()
        turn()


@check
def every_mouse_move_of_a_stroke_is_captured_while_the_view_redraws():
    """A circle drawn with real pointer motion: QCursor.setPos warps the X pointer, so the
    moves come from the X server as a mouse's do. The event loop turns (and the view
    redraws, in Mesa's software renderer under Xvfb) after every 4 moves, 4 ms apart, as
    when moves arrive faster than the view draws; the share that reached the stroke is
    printed. The press and release are sent events (a warp moves no button), with the
    mouse grabbed by the viewport between them, as a real press grabs it."""
    from Sketch2CADWorkbench.freecad_layer.trackers.stroke_capture import StrokeCapture

    view = FreeCADGui.ActiveDocument.ActiveView
    view.viewIsometric()
    view.fitAll()
    turn(10)
    viewport = view.graphicsView().viewport()
    dpr = viewport.devicePixelRatioF()
    capture = StrokeCapture(view, lambda: None, lambda: None)
    compressing = app().testAttribute(QtCore.Qt.AA_CompressHighFrequencyEvents)
    centre = QtCore.QPoint(viewport.width() // 2, viewport.height() // 2)
    radius, n = min(viewport.width(), viewport.height()) // 4, 240
    local = [
        QtCore.QPoint(
            centre.x() + round(radius * math.cos(2 * math.pi * i / n)),
            centre.y() + round(radius * math.sin(2 * math.pi * i / n)),
        )
        for i in range(n + 1)
    ]
    QtGui.QCursor.setPos(viewport.mapToGlobal(centre))  # hovering: no pre-highlight
    for _ in range(5):
        turn()
        time.sleep(0.05)
    assert not FreeCADGui.Selection.getPreselection().ObjectName
    modal = app().activeModalWidget()  # it would take every move the X server sends
    assert modal is None, f"a modal dialog is open: {modal.objectName()}"
    left = QtCore.Qt.LeftButton
    app().sendEvent(
        viewport,
        QtGui.QMouseEvent(
            QtCore.QEvent.MouseButtonPress, local[0], left, left, QtCore.Qt.NoModifier
        ),
    )
    viewport.grabMouse()  # as a real press does: the moves go to the viewport, whatever is over it
    start = time.perf_counter()
    for i, p in enumerate(local[1:]):
        QtGui.QCursor.setPos(viewport.mapToGlobal(p))
        time.sleep(0.004)
        if i % 4 == 3:
            app().processEvents()
    for _ in range(20):  # the last moves still on their way from the X server
        turn()
        time.sleep(0.02)
    seconds = time.perf_counter() - start
    viewport.releaseMouse()
    app().sendEvent(
        viewport,
        QtGui.QMouseEvent(
            QtCore.QEvent.MouseButtonRelease,
            local[-1],
            left,
            QtCore.Qt.NoButton,
            QtCore.Qt.NoModifier,
        ),
    )
    turn()
    try:
        (stroke,) = capture.strokes
        got = len(stroke) - 1  # the press's point is not a move
        say(f"FIGURE mouse_moves_captured {got}/{n} = {got / n:.0%} in {seconds:.1f} s")
        strokes, _cam = capture.result()
        sent = np.array([(p.x() * dpr + 0.5, p.y() * dpr + 0.5) for p in local], float)
        missed = [
            i for i, p in enumerate(sent) if np.min(np.linalg.norm(strokes[0] - p, axis=1)) > 0.75
        ]
        assert got >= 0.99 * n, (got, n, "missed moves", missed)
        assert app().testAttribute(QtCore.Qt.AA_CompressHighFrequencyEvents) == compressing
        far = max(float(np.min(np.linalg.norm(sent - q, axis=1))) for q in strokes[0])
        assert far <= 1.5, far  # each captured point is one the pointer went through
        assert capture.lines.numVertices.getValues()[0] == len(stroke)  # the overlay follows
    finally:
        capture.remove()
        turn()


def main():
    try:
        finish(run_checks())
    finally:
        GATE.set()


QtCore.QTimer.singleShot(0, main)
