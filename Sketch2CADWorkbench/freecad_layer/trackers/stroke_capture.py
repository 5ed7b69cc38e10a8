# SPDX-License-Identifier: LGPL-2.1-or-later
"""Capturing freehand strokes over the 3D view, drawn as an overlay while drawing.

Left-drag draws a stroke; Enter finishes; Escape cancels; the other buttons and the wheel
still navigate. The events are taken by an SoEventCallback placed first under the
viewer's root, with the viewer redirecting events to the scene graph: otherwise
navigation styles such as Gesture eat left drags, and FreeCAD's selection node (which
selects on button release, and is what view.addEventCallbackPivy sits under) eats the
release that ends a stroke. The overlay is an SoAnnotation, so the model never hides it.

Each stroke point is kept in world coordinates, on the camera's focal plane at the time
it was drawn. `result()` projects them with the camera of that moment, so zooming or
panning between strokes keeps them where they were drawn over the model.
"""
import numpy as np
from pivy import coin
from PySide import QtCore

from .view_camera import to_pixels, view_camera

EVENTS = (coin.SoMouseButtonEvent, coin.SoLocation2Event, coin.SoKeyboardEvent)
FINISH_KEYS = (coin.SoKeyboardEvent.RETURN, coin.SoKeyboardEvent.PAD_ENTER)
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
        view_camera(view)  # fails now, before anything is installed, if the view is perspective
        self.was_redirected = view.getViewer().isRedirectedToSceneGraph()
        view.getViewer().setRedirectToSceneGraph(True)
        self.events = coin.SoEventCallback()
        for kind in EVENTS:
            self.events.addEventCallback(kind.getClassTypeId(), self.event)
        self.top = view.getViewer().getSoRenderManager().getSceneGraph()
        self.top.insertChild(self.events, 0)
        self.root = coin.SoAnnotation()
        style = coin.SoDrawStyle()
        style.lineWidth = LINE_WIDTH
        colour = coin.SoBaseColor()
        colour.rgb = COLOUR
        self.coords = coin.SoCoordinate3()
        self.lines = coin.SoLineSet()
        for node in (style, colour, self.coords, self.lines):
            self.root.addChild(node)
        self.graph = view.getSceneGraph()  # after the camera, unlike the root's first child
        self.graph.addChild(self.root)

    def _world(self, position) -> np.ndarray:
        """A Coin mouse position as the world point under it on the focal plane (mm)."""
        cam = view_camera(self.view)
        depth = self.view.getCameraNode().focalDistance.getValue()
        return cam.unproject(to_pixels([position], cam.height), depth)[0]

    def event(self, _userdata, event_cb):
        """The Coin event callback: left button strokes, Enter and Escape."""
        ev = event_cb.getEvent()
        if ev.isOfType(coin.SoMouseButtonEvent.getClassTypeId()):
            if ev.getButton() != coin.SoMouseButtonEvent.BUTTON1:
                return  # navigation keeps the other buttons and the wheel
            if ev.getState() == coin.SoButtonEvent.DOWN:
                self.strokes.append([self._world(_xy(ev.getPosition()))])
                self.drawing = True
            elif self.drawing:
                self.drawing = False
                if len(self.strokes[-1]) < 2:
                    self.strokes.pop()  # a click, not a stroke
                self.redraw()
            event_cb.setHandled()
        elif ev.isOfType(coin.SoLocation2Event.getClassTypeId()) and self.drawing:
            self.strokes[-1].append(self._world(_xy(ev.getPosition())))
            self.redraw()
            event_cb.setHandled()
        elif ev.isOfType(coin.SoKeyboardEvent.getClassTypeId()) \
                and ev.getState() == coin.SoButtonEvent.DOWN:
            if ev.getKey() in FINISH_KEYS:
                event_cb.setHandled()
                QtCore.QTimer.singleShot(0, self.on_finish)
            elif ev.getKey() == coin.SoKeyboardEvent.ESCAPE:
                event_cb.setHandled()
                QtCore.QTimer.singleShot(0, self.on_cancel)

    def redraw(self) -> None:
        """Update the overlay's coordinates (only fields change: safe inside a callback)."""
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
        self.view.getViewer().setRedirectToSceneGraph(self.was_redirected)
        top, events, graph, root = self.top, self.events, self.graph, self.root
        QtCore.QTimer.singleShot(0, lambda: (top.removeChild(events), graph.removeChild(root)))


def _xy(position) -> tuple:
    """An SbVec2s as (x, y): indexing works in every pivy, while getValue() returns an
    opaque SWIG pointer in FreeCAD 1.1's."""
    return float(position[0]), float(position[1])
