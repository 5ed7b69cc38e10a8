# SPDX-License-Identifier: LGPL-2.1-or-later
"""The Sketch task panel: strokes captured over the view, read by the interpret pipeline,
the reading and its preview shown, the designer's choices, accept or discard."""
import FreeCADGui
from PySide import QtGui

from ...brep.protocol import Mode, Operation, describe, operation_to_dict
from ..gui_helpers import error, transaction
from ..networks import loading, predictor, when_loaded
from ..shapes import from_part, to_part
from ..trackers.preview import Preview
from ..trackers.stroke_capture import StrokeCapture


def add_operation_command(model, op: Operation) -> str:
    """The console line that appends `op` to `model` (make_model.add_operation)."""
    return (f"Sketch2CADWorkbench.freecad_layer.make.make_model.add_operation("
            f"FreeCAD.getDocument({model.Document.Name!r}).getObject({model.Name!r}), "
            f"Sketch2CADWorkbench.brep.protocol.operation_from_dict("
            f"{operation_to_dict(op)!r}))")


class SketchPanel:
    """The task panel: what the strokes were read as, the designer's choices, accept/discard."""

    def __init__(self, model):
        self.model = model
        self.doc = model.Document
        self.view = FreeCADGui.ActiveDocument.ActiveView
        self.result = None
        self.preview = Preview(self.view)
        self.form = self._build_form()
        self.capture = StrokeCapture(self.view, self.interpret, self.cancel)
        if loading():  # started with the workbench (freecad_layer/networks.py)
            self.text.setHtml("<i>Loading networks…</i> You can draw meanwhile.")
            when_loaded(lambda: self.text.toPlainText().startswith("Loading networks")
                        and self.text.setHtml("Networks ready."), self.text)

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
        from ...inference.interpret import InterpretOptions
        opt = self.option.currentText()
        sym = self.symmetry.currentText()
        return InterpretOptions(self.regularize.isChecked(),
                                None if opt == "auto" else Mode(opt),
                                None if sym == "none" else sym)

    def reinterpret(self, *_):
        if self.capture.strokes:
            self.interpret()

    def interpret(self):
        strokes, camera = self.capture.result()
        self.result = None
        self.preview.show(None)
        if not strokes:
            self.text.setHtml("<b>No strokes yet.</b> Draw over the model first.")
            return
        if loading():
            self.text.setHtml("<i>Loading networks…</i> The reading follows when they "
                              "are ready.")
            self.text.repaint()  # the import and predictor() below wait for the load
        from ...inference.interpret import InterpretError, interpret
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
        if r.doubtful:
            other += f"<p style='color:#b60'><b>Warning:</b> {r.doubt()}.</p>"
        self.text.setHtml(f"<b>Read as {r.op_type.value}</b> ({probs})<ul>{lines}</ul>{other}"
                          f"{r.timings_ms['total']:.0f} ms. OK adds it to the model.")
        self.preview.show(to_part(r.solid))

    def clear(self):
        self.capture.clear()
        self.result = None
        self.preview.show(None)
        self.text.clear()

    def _close(self):
        self.preview.show(None)
        self.capture.remove()
        FreeCADGui.Control.closeDialog()

    def accept(self):
        if self.result is None:
            self.interpret()
            if self.result is None:
                return False  # stays open with the reason shown
        try:
            with transaction(self.doc, "Sketch2CAD sketch"):
                # through the console, as Draft's tools do: each step lands in macros
                FreeCADGui.addModule("Sketch2CADWorkbench.freecad_layer.make.make_model")
                FreeCADGui.addModule("Sketch2CADWorkbench.brep.protocol")
                for op in self.result.operations:
                    FreeCADGui.doCommand(add_operation_command(self.model, op))
                FreeCADGui.doCommand(f"FreeCAD.getDocument({self.doc.Name!r}).recompute()")
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
