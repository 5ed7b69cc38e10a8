# SPDX-License-Identifier: LGPL-2.1-or-later
"""Inside FreeCAD: the checks' registry, their report lines and the exit code.

Each check prints "CHECK PASSED <name>" or "CHECK FAILED <name>" and its traceback; the
process exits 1 if any failed (freecadcmd itself exits 0 on an uncaught exception).
"""

import os
import sys
import traceback

ROOT = os.environ["SKETCH2CAD_ROOT"]
TMP = os.environ["SKETCH2CAD_TMP"]
EXAMPLES = os.path.join(ROOT, "examples", "protocols")
CHECKS = []


def check(fn):
    """Register a check (run in registration order by `run_checks`)."""
    CHECKS.append(fn)
    return fn


def close(a: float, b: float, rel: float = 1e-6) -> bool:
    return abs(a - b) <= rel * max(abs(a), abs(b))


def say(line: str) -> None:
    # sys.__stdout__: FreeCAD 1.0's GUI sends sys.stdout to the report view only. On its
    # own line: FreeCAD's progress output has no newline.
    print(f"\n{line}", file=sys.__stdout__, flush=True)


def tested_checkout() -> None:
    """The Sketch2CAD that FreeCAD loaded (through its Mod folder) is this checkout."""
    import Sketch2CADWorkbench

    loaded = os.path.realpath(os.path.dirname(Sketch2CADWorkbench.__file__))
    wanted = os.path.realpath(os.path.join(ROOT, "Sketch2CADWorkbench"))
    assert loaded == wanted, (
        f"FreeCAD loaded Sketch2CAD from {loaded}, not {wanted}: "
        "run scripts/setup.sh to link this checkout into its Mod folder"
    )


def send_drag(viewport, pixels, button=None) -> None:
    """A mouse drag through core pixel positions, as Qt events sent to the view's viewport
    (in device-independent pixels: Xvfb's 96 dpi makes Qt scale by about 1.04), each with
    its screen position, as the window system gives it, the pointer put where it starts."""
    from PySide import QtCore, QtGui

    button = button or QtCore.Qt.LeftButton
    dpr = viewport.devicePixelRatioF()
    points = [QtCore.QPointF(int(x / dpr), int(y / dpr)) for x, y in pixels]
    send = QtGui.QApplication.instance().sendEvent

    def event(kind, p, which, held):
        screen = QtCore.QPointF(viewport.mapToGlobal(p.toPoint()))
        return QtGui.QMouseEvent(kind, p, screen, which, held, QtCore.Qt.NoModifier)

    QtGui.QCursor.setPos(viewport.mapToGlobal(points[0].toPoint()))
    send(viewport, event(QtCore.QEvent.MouseButtonPress, points[0], button, button))
    for p in points[1:]:
        send(viewport, event(QtCore.QEvent.MouseMove, p, QtCore.Qt.NoButton, button))
    send(viewport, event(QtCore.QEvent.MouseButtonRelease, points[-1], button, QtCore.Qt.NoButton))


def run_checks() -> int:
    """Run every registered check; 0 if all passed, else 1."""
    failed = 0
    for fn in CHECKS:
        try:
            fn()
            say(f"CHECK PASSED {fn.__name__}")
        except Exception:
            failed += 1
            say(f"CHECK FAILED {fn.__name__}")
            traceback.print_exc(file=sys.__stdout__)
    return 1 if failed else 0


def finish(code: int) -> None:
    """Leave FreeCAD now with `code` (its own exit would not pass it on)."""
    for stream in (sys.stdout, sys.stderr, sys.__stdout__, sys.__stderr__):
        stream.flush()
    os._exit(code)
