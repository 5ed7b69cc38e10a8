# SPDX-License-Identifier: LGPL-2.1-or-later
"""The networks the workbench interprets with, loaded once per FreeCAD session.

Importing cadquery, torch and the interpret pipeline and reading the weights takes seconds
(docs/measurements.md, "The networks loaded in a background thread"), so the workbench
starts it in a background thread when it is activated (`load_in_background`), while the
user draws; the status bar says so
(`show_status`) and so does the Sketch panel (`when_loaded`). `predictor()` waits for
that load instead of starting a second one, and loads in the calling thread when none was
started (freecadcmd, scripts).

The thread only imports modules and reads the weights file: it never touches a FreeCAD
object or a widget, which belong to the GUI thread. It still holds the GIL in stretches
(OCP's module initialisation is one long C++ call), when the GUI stalls; the GUI check
prints the longest stall (tests/freecad/scripts/responsiveness_session.py).
"""

import threading
import time

# Leaves first: a module the GUI thread imports meanwhile (a command on first use) then
# only waits for the thread's import of the leaf, never the other way round.
PRELOAD = (
    "cadquery",
    "torch",
    "Sketch2CADWorkbench.brep.operators",
    "Sketch2CADWorkbench.inference.interpret",
)
STATUS_MS = 5000  # how long "networks ready" stays in the status bar
POLL_MS = 200  # how often the GUI thread looks whether the load has ended

_lock = threading.Lock()
_thread = None  # the background load, while it runs and after
_predictor = None
_error = None  # what the background load raised, as text for the status bar
_seconds = None  # how long the background load took


def _load():
    """The predictor: the PRELOAD modules imported, the shipped weights read."""
    import importlib

    for name in PRELOAD:
        importlib.import_module(name)
    from ..inference.weights import load_predictor

    return load_predictor()


def _background():
    global _predictor, _error, _seconds
    start = time.perf_counter()
    try:
        p = _load()
        with _lock:
            _predictor = p
    except Exception as e:  # reported in the status bar; predictor() retries and raises it
        _error = f"{type(e).__name__}: {e}"
    _seconds = time.perf_counter() - start


def start_loading() -> bool:
    """Load the networks in a background thread, unless they are loaded or loading.

    Returns:
        Whether this call started it.
    """
    global _thread
    with _lock:
        if _predictor is not None or _thread is not None:
            return False
        _thread = threading.Thread(target=_background, name="Sketch2CAD networks", daemon=True)
        _thread.start()
        return True


def load_in_background() -> None:
    """`start_loading`, and `show_status` when that started the load (the workbench's
    activation calls this)."""
    if start_loading():
        show_status()


def loading() -> bool:
    """Whether the background load is still running."""
    return _thread is not None and _thread.is_alive()


def predictor():
    """The shipped networks (inference.weights.load_predictor): waits for the background
    load when one runs, loads them here when none ran or it failed (raising its error:
    FileNotFoundError for missing weights, ImportError for a missing dependency)."""
    global _predictor
    if _thread is not None:
        _thread.join()
    with _lock:
        if _predictor is None:
            _predictor = _load()
        return _predictor


def when_loaded(fn, parent) -> None:
    """Call `fn()` in the GUI thread once the background load has ended (at once when none
    runs). The poll is a timer owned by the QObject `parent`: it ends with it (a closed
    task panel's widget), so `fn` never sees a deleted widget."""
    from PySide import QtCore

    timer = QtCore.QTimer(parent)

    def poll():
        if not loading():
            timer.stop()
            timer.deleteLater()
            fn()

    timer.timeout.connect(poll)
    timer.start(POLL_MS)


def show_status() -> None:
    """While the networks load, a "loading networks" label in the main window's status bar
    (a permanent widget: FreeCAD's own messages there do not hide it), then for a while
    that they are ready, or why not."""
    import FreeCADGui
    from PySide import QtCore, QtGui

    bar = FreeCADGui.getMainWindow().statusBar()
    label = QtGui.QLabel("Sketch2CAD: loading networks\u2026 (you can draw meanwhile)")
    label.setObjectName("Sketch2CADNetworksStatus")
    bar.addPermanentWidget(label)

    def loaded():
        if _error:
            label.setText(f"Sketch2CAD: the networks did not load: {_error}")
            label.setToolTip(_error)
        else:
            label.setText(f"Sketch2CAD: networks ready ({_seconds:.1f} s)")
        QtCore.QTimer.singleShot(STATUS_MS, label.deleteLater)

    when_loaded(loaded, label)
