# SPDX-License-Identifier: LGPL-2.1-or-later
"""Capturing freehand strokes over the 3D view, drawn as an overlay while drawing.

Left-drag draws a stroke (one that starts on the view's own area, not on a widget over it);
Enter finishes; Escape cancels; the other buttons and the wheel
still navigate. The mouse is read by a Qt event filter on the view's viewport, before
Coin sees it: each move costs a point, not a pass through the scene graph, and the
overlay is updated once per turn of the event loop, so the view redraws at its own rate
while every move is kept. While the left button is down Qt's merging of queued mouse
moves (AA_CompressHighFrequencyEvents, on by default on X11) is off: with it, a view
that renders slowly (software OpenGL) received a quarter of the moves and circles came
out as polygons. Left presses, moves and releases and the hover moves
never reach Coin, so navigation styles do not take left drags and faces do not
pre-highlight while drawing. Enter and Escape are read by the same filter, on the view
and its viewport (whichever has the keyboard focus). The viewer's Python object
(`view.getViewer()`) is never asked for: FreeCAD 1.1.3 with Python 3.14 crashes when a
document whose viewer it handed out is closed.
The overlay is an SoAnnotation, so the model never hides it.

Each stroke point is kept in world coordinates, on the camera's focal plane at the time
it was drawn. `result()` projects them with the camera of that moment, so zooming or
panning between strokes keeps them where they were drawn over the model.
"""

import numpy as np
from pivy import coin
from PySide import QtCore, QtGui

from .view_camera import from_qt, view_camera

FINISH_KEYS = (QtCore.Qt.Key_Return, QtCore.Qt.Key_Enter)  # Enter: the keypad's
KEYS = FINISH_KEYS + (QtCore.Qt.Key_Escape,)
KEY_EVENTS = (QtCore.QEvent.ShortcutOverride, QtCore.QEvent.KeyPress, QtCore.QEvent.KeyRelease)
COLOUR = (1.0, 0.55, 0.0)  # orange: the paper's sketch colour, visible on grey models
LINE_WIDTH = 3.0  # pixels


class StrokeCapture:
    """Strokes drawn with the left mouse button over a 3D view.

    Args:
        view: the 3D view (FreeCADGui.ActiveDocument.ActiveView); it must be orthographic.
        on_finish: called without arguments (outside the event handler) on Enter.
        on_cancel: called likewise on Escape.

    The caller reads `result()` in on_finish and calls `remove()` when done.
    """

    def __init__(self, view, on_finish, on_cancel):
        self.view = view
        self.on_finish, self.on_cancel = on_finish, on_cancel
        self.strokes: list[list[np.ndarray]] = []  # world points (mm), one list per stroke
        self.drawing = False
        self.redraw_pending = False
        view_camera(view)  # fails now, before anything is installed, if the view is perspective
        self.root = coin.SoAnnotation()
        style = coin.SoDrawStyle()
        style.lineWidth = LINE_WIDTH
        colour = coin.SoBaseColor()
        colour.rgb = COLOUR
        self.coords = coin.SoCoordinate3()
        self.lines = coin.SoLineSet()
        for node in (style, colour, self.coords, self.lines):
            self.root.addChild(node)
        self.graph = view.getSceneGraph()  # after the camera
        self.graph.addChild(self.root)
        graphics_view = view.graphicsView()
        self.widgets = (graphics_view, graphics_view.viewport())
        self.filter = _EventFilter(self)
        for widget in self.widgets:
            widget.installEventFilter(self.filter)
        self.compressing = QtGui.QApplication.testAttribute(
            QtCore.Qt.AA_CompressHighFrequencyEvents
        )

    def _world(self, pixel) -> np.ndarray:
        """A core pixel (origin top-left) as the world point under it on the focal plane (mm)."""
        cam = view_camera(self.view)
        depth = self.view.getCameraNode().focalDistance.getValue()
        return cam.unproject(np.array([pixel], float), depth)[0]

    def press(self, pixel) -> None:
        """The left button went down at a core pixel: a stroke begins."""
        self.strokes.append([self._world(pixel)])
        self.drawing = True
        # every queued move is kept until the release (see the module's docstring)
        QtGui.QApplication.setAttribute(QtCore.Qt.AA_CompressHighFrequencyEvents, False)

    def move(self, pixel) -> None:
        """The mouse moved to a core pixel while drawing."""
        self.strokes[-1].append(self._world(pixel))
        if not self.redraw_pending:  # one overlay update per turn of the event loop
            self.redraw_pending = True
            QtCore.QTimer.singleShot(0, self.redraw)

    def release(self) -> None:
        """The left button went up: the stroke ends (a click is not a stroke)."""
        self.drawing = False
        QtGui.QApplication.setAttribute(QtCore.Qt.AA_CompressHighFrequencyEvents, self.compressing)
        if len(self.strokes[-1]) < 2:
            self.strokes.pop()
        self.redraw()

    def key(self, qt_key) -> None:
        """Enter (or the keypad's) was pressed: finish; Escape: cancel."""
        if qt_key in FINISH_KEYS:
            QtCore.QTimer.singleShot(0, self.on_finish)
        elif qt_key == QtCore.Qt.Key_Escape:
            QtCore.QTimer.singleShot(0, self.on_cancel)

    def redraw(self) -> None:
        """Update the overlay's coordinates (only fields change: safe inside a callback)."""
        self.redraw_pending = False
        points = [tuple(p) for s in self.strokes for p in s]
        counts = [len(s) for s in self.strokes]
        self.coords.point.setValues(0, len(points), points)
        self.coords.point.setNum(len(points))
        self.lines.numVertices.setValues(0, len(counts), counts)
        self.lines.numVertices.setNum(len(counts))

    def result(self):
        """The strokes in the view's current camera.

        Returns:
            (strokes, camera): a list of (K, 2) arrays of core pixels (origin top-left,
            y down), one per stroke of at least 2 points, and the view's OrthoCamera.
        """
        cam = view_camera(self.view)
        return [cam.project(np.array(s))[0] for s in self.strokes if len(s) >= 2], cam

    def clear(self) -> None:
        """Forget the strokes drawn so far."""
        self.strokes = []
        self.drawing = False
        self.redraw()

    def remove(self) -> None:
        """Stop capturing; the nodes are taken away once outside any event handler."""
        for widget in self.widgets:
            widget.removeEventFilter(self.filter)
        # no wrapper of the view's widgets outlives the capture: PySide2 hands a stale one
        # ("already deleted") to a later view whose widget reuses the address
        self.widgets = ()
        if self.drawing:  # removed with the button down: Qt merges moves again
            QtGui.QApplication.setAttribute(
                QtCore.Qt.AA_CompressHighFrequencyEvents, self.compressing
            )
            self.drawing = False
        graph, root = self.graph, self.root
        QtCore.QTimer.singleShot(0, lambda: graph.removeChild(root))


class _EventFilter(QtCore.QObject):
    """The view's mouse and key events for a StrokeCapture (see the module's docstring)."""

    def __init__(self, capture: StrokeCapture):
        super().__init__()
        self.capture = capture

    def eventFilter(self, widget, event) -> bool:
        kind, c = event.type(), self.capture
        if kind in KEY_EVENTS and event.key() in KEYS:
            if kind == QtCore.QEvent.ShortcutOverride:
                event.accept()  # so the key comes as a KeyPress, not as a menu's shortcut
            elif kind == QtCore.QEvent.KeyPress and not event.isAutoRepeat():
                c.key(event.key())
            return True
        if isinstance(widget, QtGui.QAbstractScrollArea):
            return False  # the view itself: mouse events are the viewport's
        # a quick second stroke begins with a double-click event, not FreeCAD's double-click
        if (
            kind in (QtCore.QEvent.MouseButtonPress, QtCore.QEvent.MouseButtonDblClick)
            and event.button() == QtCore.Qt.LeftButton
        ):
            if not _on_the_view(widget):
                return False  # an overlay panel's edge or handle (FreeCAD 1.1's overlay mode)
            c.press(_pixel(widget, event))
            return True
        if kind == QtCore.QEvent.MouseMove and c.drawing:
            c.move(_pixel(widget, event))
            return True
        if kind == QtCore.QEvent.MouseButtonRelease and event.button() == QtCore.Qt.LeftButton:
            if c.drawing:
                c.release()
            return True
        # hover moves too: no pre-highlighting of faces while drawing; moves with another
        # button down (navigation) go on to Coin
        return kind == QtCore.QEvent.MouseMove and event.buttons() == QtCore.Qt.NoButton


def _position(event):
    """A Qt mouse event's position in its widget (device-independent pixels)."""
    return event.position() if hasattr(event, "position") else event.localPos()  # Qt6 / Qt5


def _on_the_view(viewport) -> bool:
    """The pointer is on the 3D view's own area, not on one of FreeCAD 1.1's overlay panels
    over it (their edges, handles and title bars included): the overlay mode passes presses
    on a panel's see-through edges on to the view, at another place in it than the
    pointer's; a drag from there resizes the panel, it is no stroke."""
    w = QtGui.QApplication.widgetAt(QtGui.QCursor.pos())
    while w is not None and w != viewport:
        if "Overlay" in w.metaObject().className():  # Gui::OverlayTabWidget, its parts
            return False
        w = w.parentWidget()
    return True


def _pixel(widget, event) -> tuple:
    """A Qt mouse event's position (device-independent pixels) as a core pixel."""
    pos = _position(event)
    return from_qt((pos.x(), pos.y()), widget.devicePixelRatioF())
