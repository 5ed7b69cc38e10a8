# SPDX-License-Identifier: LGPL-2.1-or-later
"""Sketch: strokes over the 3D view -> the interpreted operation -> a new feature."""
import FreeCADGui
from PySide import QtGui
from pivy import coin

from ..brep.protocol import Mode, describe
from ..freecad_layer.make.make_model import add_operation
from ..freecad_layer.shapes import from_part, to_part
from ..freecad_layer.stroke_capture import StrokeCapture
from .common import active_model, error, resources, transaction

_PREDICTOR = None


def predictor():
    """The networks, loaded on first use (torch and the weights are not needed before)."""
    global _PREDICTOR
    if _PREDICTOR is None:
        from ..inference.weights import load_predictor
        _PREDICTOR = load_predictor()
    return _PREDICTOR


class Sketch:
    def GetResources(self):
        return resources("Sketch", "Sketch an operation",
                         "Draw strokes over the model (left drag); Enter interprets them as "
                         "an extrude, bevel, add/subtract prism or sweep; Esc cancels", "S, S")

    def IsActive(self):
        return active_model() is not None and FreeCADGui.Control.activeDialog() is False

    def Activated(self):
        FreeCADGui.Control.showDialog(SketchPanel(active_model()))


class SketchPanel:
    """The task panel: what the strokes were read as, the designer's choices, accept/discard."""

    def __init__(self, model):
        self.model = model
        self.doc = model.Document
        self.view = FreeCADGui.ActiveDocument.ActiveView
        self.result = None
        self.preview = None
        self.form = self._build_form()
        self.capture = StrokeCapture(self.view, self.interpret, self.cancel)

    def _build_form(self):
        w = QtGui.QWidget()
        w.setWindowTitle("Sketch2CAD sketch")
        lay = QtGui.QVBoxLayout(w)
        hint = QtGui.QLabel("Draw the operation's strokes over the model (left drag), "
                            "then press Enter or Interpret. Esc cancels.")
        hint.setWordWrap(True)  # else its one long line widens the panel past the combo view
        lay.addWidget(hint)
        self.regularize = QtGui.QCheckBox("Regularize (snap and rectify)")
        self.regularize.setChecked(True)
        self.option = QtGui.QComboBox()
        self.option.addItems(["auto", *[m.value for m in Mode]])
        self.symmetry = QtGui.QComboBox()
        self.symmetry.addItems(["none", "x", "y", "z"])
        form = QtGui.QFormLayout()
        form.addRow("Boolean", self.option)
        form.addRow("Mirror through mid-plane", self.symmetry)
        lay.addLayout(form)
        lay.addWidget(self.regularize)
        buttons = QtGui.QHBoxLayout()
        self.interpret_button = QtGui.QPushButton("Interpret")
        self.clear_button = QtGui.QPushButton("Clear strokes")
        buttons.addWidget(self.interpret_button)
        buttons.addWidget(self.clear_button)
        lay.addLayout(buttons)
        self.text = QtGui.QTextEdit()
        self.text.setReadOnly(True)
        lay.addWidget(self.text)
        self.interpret_button.clicked.connect(self.interpret)
        self.clear_button.clicked.connect(self.clear)
        for box in (self.option, self.symmetry):
            box.currentIndexChanged.connect(self.reinterpret)
        self.regularize.toggled.connect(self.reinterpret)
        return w

    def options(self):
        from ..inference.interpret import InterpretOptions
        opt = self.option.currentText()
        sym = self.symmetry.currentText()
        return InterpretOptions(self.regularize.isChecked(),
                                None if opt == "auto" else Mode(opt),
                                None if sym == "none" else sym)

    def reinterpret(self, *_):
        if self.capture.strokes:
            self.interpret()

    def interpret(self):
        from ..inference.interpret import InterpretError, interpret
        strokes, camera = self.capture.result()
        self.result = None
        self._show_preview(None)
        if not strokes:
            self.text.setHtml("<b>No strokes yet.</b> Draw over the model first.")
            return
        try:
            solid = from_part(self.model.Tip.Shape)
            self.result = interpret(solid, strokes, camera, predictor(), options=self.options())
        except (InterpretError, ValueError, FileNotFoundError) as e:
            self.text.setHtml(f"<b style='color:#b00'>Not interpreted:</b> {e}<br>"
                              "Nothing was changed. Add or clear strokes and try again.")
            return
        r = self.result
        probs = ", ".join(f"{k} {v:.0%}" for k, v in r.probabilities.items())
        lines = "".join(f"<li>{describe(op)}</li>" for op in r.operations)
        other = ""
        if r.other_option is not None:  # a boss and a hole that draw the same lines
            other = (f"<p>The strokes read just as well as <b>{r.other_option.value}</b>: "
                     f"from this view its primitive draws the same lines. Set Boolean to "
                     f"{r.other_option.value} if that was meant.</p>")
        self.text.setHtml(f"<b>Read as {r.op_type.value}</b> ({probs})<ul>{lines}</ul>{other}"
                          f"{r.timings_ms['total']:.0f} ms. OK adds it to the model.")
        self._show_preview(to_part(r.solid))

    def _show_preview(self, shape):
        graph = self.view.getSceneGraph()
        if self.preview is not None:
            graph.removeChild(self.preview)
            self.preview = None
        if shape is None:
            return
        node = coin.SoSeparator()
        mat = coin.SoMaterial()
        mat.diffuseColor = (0.3, 0.75, 0.4)
        mat.transparency = 0.45
        node.addChild(mat)
        node.addChild(_mesh_node(shape))
        graph.addChild(node)
        self.preview = node

    def clear(self):
        self.capture.clear()
        self.result = None
        self._show_preview(None)
        self.text.clear()

    def _close(self):
        self._show_preview(None)
        self.capture.remove()
        FreeCADGui.Control.closeDialog()

    def accept(self):
        if self.result is None:
            self.interpret()
            if self.result is None:
                return False  # stays open with the reason shown
        try:
            with transaction(self.doc, "Sketch2CAD sketch"):
                for op in self.result.operations:
                    add_operation(self.model, op)
                self.doc.recompute()
        except Exception as e:  # the transaction was aborted: the document is as before
            error("Cannot add the operation", str(e))
            return False
        self._close()
        return True

    def reject(self):
        self._close()
        return True

    def cancel(self):
        self.reject()

    def getStandardButtons(self):
        flags = QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Cancel
        return int(getattr(flags, "value", flags))  # PySide6's flags are enums: int() fails


def _mesh_node(shape, tolerance: float = 0.1):
    """Coin nodes of the shape's triangles (built directly: the text of writeInventor()
    differs between FreeCAD versions, and FreeCAD 1.0's is not read back by Coin)."""
    points, triangles = shape.tessellate(tolerance)
    group = coin.SoGroup()
    coords = coin.SoCoordinate3()
    coords.point.setValues(0, len(points), [(p.x, p.y, p.z) for p in points])
    faces = coin.SoIndexedFaceSet()
    faces.coordIndex.setValues(0, 4 * len(triangles),
                               [i for tri in triangles for i in (*tri, -1)])
    group.addChild(coords)
    group.addChild(faces)
    return group
