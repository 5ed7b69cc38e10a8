# SPDX-License-Identifier: LGPL-2.1-or-later
"""The Sketch task panel: strokes captured over the view, read by the interpret pipeline,
the reading and its preview shown (in the user's units), the designer's choices, accept
or discard. The same panel re-opens a sketched step (double-click in the tree): its
strokes are shown again in the view they were drawn in, and OK applies the new reading
to that step."""

import json

import FreeCAD
import FreeCADGui
import numpy as np
from PySide import QtGui

from ...brep.protocol import Mode, Operation, operation_to_dict
from ..gui_helpers import error, transaction
from ..networks import loading, predictor, when_loaded
from ..preferences import regularize_default, snap_step, use_network_threads
from ..shapes import from_part, to_part
from ..trackers.preview import Preview
from ..trackers.stroke_capture import StrokeCapture
from ..translate import translate

MAKE = "Sketch2CADWorkbench.freecad_layer.make.make_model"


def tr(text: str) -> str:
    return translate("Sketch2CAD", text)


def _call(function: str, target: str, op: Operation, sketch: str) -> str:
    return (
        f"{MAKE}.{function}({target}, Sketch2CADWorkbench.brep.protocol.operation_from_dict("
        f"{operation_to_dict(op)!r}){f', sketch={sketch!r}' if sketch else ''})"
    )


def add_operation_command(model, op: Operation, sketch: str = "") -> str:
    """The console line that appends `op` to `model` (make_model.add_operation), with the
    sketch it was read from (JSON, see add_operation)."""
    return _call(
        "add_operation",
        f"FreeCAD.getDocument({model.Document.Name!r}).getObject({model.Name!r})",
        op,
        sketch,
    )


def replace_operation_command(obj, op: Operation, sketch: str = "") -> str:
    """The console line that makes the feature `obj` stand for `op`
    (make_model.replace_operation)."""
    return _call(
        "replace_operation",
        f"FreeCAD.getDocument({obj.Document.Name!r}).getObject({obj.Name!r})",
        op,
        sketch,
    )


def set_view_camera(view, cam) -> None:
    """Point the 3D view's orthographic camera as `cam` (an OrthoCamera): the view a step
    was sketched in."""
    d = np.asarray(cam.direction, float)
    d /= np.linalg.norm(d)
    u = np.asarray(cam.up, float)
    u = u - u.dot(d) * d
    u /= np.linalg.norm(u)
    x, z = np.cross(d, u), -d  # the camera's right, up (u) and backwards axes
    m = FreeCAD.Matrix(x[0], u[0], z[0], 0, x[1], u[1], z[1], 0, x[2], u[2], z[2], 0)
    node = view.getCameraNode()
    node.orientation.setValue(*FreeCAD.Rotation(m).Q)
    node.position.setValue(*map(float, cam.center))
    w, h = view.getSize()
    node.height.setValue(2.0 * cam.scale / max(1.0, h / w))


class SketchPanel:
    """The task panel: what the strokes were read as, the designer's choices, accept/discard.

    Args:
        model: the model to sketch on.
        feature: a sketched step of the model to read again (its panel re-opened), or
            None for a new step after the model's Tip.

    Raises:
        ValueError: the view is perspective (from the stroke capture).
    """

    def __init__(self, model, feature=None):
        self.model = model
        self.feature = feature
        self.doc = model.Document
        self.view = FreeCADGui.ActiveDocument.ActiveView
        self.result = None
        self.step = None  # the SketchStep the result was read from
        self.preview = Preview(self.view)
        self.form = self._build_form()
        self.capture = StrokeCapture(self.view, self.interpret, self.cancel)
        self.shown = None  # features' visibility before an edit
        self.closed = False
        self.skipped = set()  # SNAP_KINDS keys the designer undid for these strokes
        self.snap_buttons = []
        if feature is not None:
            self._open_feature()
        if loading():  # started with the workbench (freecad_layer/networks.py)
            self.text.setHtml(tr("<i>Loading networks…</i> You can draw meanwhile."))
            when_loaded(
                lambda: (
                    self.text.toPlainText().startswith(tr("Loading networks"))
                    and self.text.setHtml(tr("Networks ready."))
                ),
                self.text,
            )

    def _build_form(self):
        w = QtGui.QWidget()
        title = (
            tr("Sketch2CAD sketch")
            if self.feature is None
            else tr("Sketch2CAD: edit {}").format(self.feature.Label)
        )
        w.setWindowTitle(title)
        lay = QtGui.QVBoxLayout(w)
        hint = QtGui.QLabel(
            tr(
                "Draw the operation's strokes over the model (left drag), "
                "then press Enter or Interpret. Esc cancels."
            )
        )
        hint.setWordWrap(True)  # else its one long line widens the panel past the combo view
        lay.addWidget(hint)
        self.regularize = QtGui.QCheckBox(tr("Regularize (snap and rectify)"))
        self.regularize.setChecked(regularize_default())
        self.option = QtGui.QComboBox()
        self.option.addItems(["auto", *[m.value for m in Mode]])
        self.symmetry = QtGui.QComboBox()
        self.symmetry.addItems(["none", "x", "y", "z"])
        form = QtGui.QFormLayout()
        # labels above their fields when the panel is narrow (FreeCAD's default combo view)
        form.setRowWrapPolicy(QtGui.QFormLayout.WrapLongRows)
        form.addRow(tr("Boolean"), self.option)
        form.addRow(tr("Mirror"), self.symmetry)
        self.symmetry.setToolTip(
            tr("Also add the mirror image through the model's mid-plane normal to this axis")
        )
        lay.addLayout(form)
        lay.addWidget(self.regularize)
        buttons = QtGui.QHBoxLayout()
        self.interpret_button = QtGui.QPushButton(tr("Interpret"))
        self.clear_button = QtGui.QPushButton(tr("Clear strokes"))
        buttons.addWidget(self.interpret_button)
        buttons.addWidget(self.clear_button)
        lay.addLayout(buttons)
        # one button per snap the reading applied: a click reads the strokes again
        # without it (InterpretOptions.skip_snaps); undone snaps stay off until cleared
        self.snap_box = QtGui.QVBoxLayout()
        lay.addLayout(self.snap_box)
        self.text = QtGui.QTextEdit()
        self.text.setReadOnly(True)
        self.text.setMinimumWidth(0)
        self.text.setMinimumHeight(260)  # the reading without scrolling, most of the time
        lay.addWidget(self.text)
        for widget in (self.option, self.symmetry):
            # combo boxes size to their longest entry by default
            widget.setSizeAdjustPolicy(QtGui.QComboBox.AdjustToMinimumContentsLengthWithIcon)
            widget.setMinimumContentsLength(6)
        self.interpret_button.clicked.connect(self.interpret)
        self.clear_button.clicked.connect(self.clear)
        for box in (self.option, self.symmetry):
            box.currentIndexChanged.connect(self.reinterpret)
        self.regularize.toggled.connect(self.reinterpret)
        return w

    # ------------------------------------------------------------ editing a step

    def _open_feature(self) -> None:
        """Show the step's strokes in the view they were drawn in, its choices in the
        panel, the solid it applies to, and read the strokes again."""
        from ...inference.session import step_from_dict

        obj = self.feature
        # FreeCAD's tree opens an "Edit" transaction on a double-click: the step's own
        # transaction is opened by OK, and Cancel leaves no undo step (showing the solid
        # before the step is not an edit)
        if FreeCAD.getActiveTransaction():
            FreeCAD.closeActiveTransaction(True)
        if not obj.SketchStep:
            self.text.setHtml(
                tr(
                    "<b>{} keeps no strokes</b> (it came from a protocol). "
                    "Draw new strokes to replace it, or edit its values in "
                    "the property editor."
                ).format(obj.Label)
            )
            step = None
        else:
            step = step_from_dict(json.loads(obj.SketchStep))
            set_view_camera(self.view, step.camera)
            depth = self.view.getCameraNode().focalDistance.getValue()
            self.capture.strokes = [list(step.camera.unproject(s, depth)) for s in step.strokes]
            self.capture.redraw()
            c = step.choices
            self.skipped = set(c.skip_snaps)  # the snaps undone when it was drawn stay undone
            self.regularize.blockSignals(True)
            self.regularize.setChecked(c.regularize)
            self.regularize.blockSignals(False)
            for box, value in (
                (self.option, c.option.value if c.option else "auto"),
                (self.symmetry, c.symmetry or "none"),
            ):
                box.blockSignals(True)
                box.setCurrentIndex(box.findText(value))
                box.blockSignals(False)
        # the solid before this step, as PartDesign shows while a feature is edited
        self.shown = {o.Name: o.ViewObject.Visibility for o in self.model.Group}
        for o in self.model.Group:
            o.ViewObject.Visibility = o == obj.Base
        if step is not None:
            self.interpret()

    def _base_solid(self):
        base = self.model.Tip if self.feature is None else self.feature.Base
        return from_part(base.Shape)

    # ------------------------------------------------------------ reading

    def options(self):
        from ...inference.options import InterpretOptions

        opt = self.option.currentText()
        sym = self.symmetry.currentText()
        return InterpretOptions(
            self.regularize.isChecked(),
            None if opt == "auto" else Mode(opt),
            None if sym == "none" else sym,
            snap_step=snap_step(),
            skip_snaps=frozenset(self.skipped),
        )

    def undo_snap(self, key: str) -> None:
        """Read the strokes again without the snap `key` (a SNAP_KINDS key)."""
        self.skipped.add(key)
        self.reinterpret()

    def redo_snaps(self) -> None:
        self.skipped.clear()
        self.reinterpret()

    def _show_snaps(self, snaps) -> None:
        """A button per applied snap (its undo), and one to snap again what was undone."""
        while self.snap_box.count():
            w = self.snap_box.takeAt(0).widget()
            if w is not None:
                w.deleteLater()
        self.snap_buttons = []
        for snap in snaps:
            b = QtGui.QPushButton(tr("Undo snap: {}").format(snap.describe()))
            b.setToolTip(tr("Read the strokes again without this snap"))
            b.clicked.connect(lambda _=False, k=snap.key: self.undo_snap(k))
            self.snap_box.addWidget(b)
            self.snap_buttons.append(b)
        if self.skipped:
            b = QtGui.QPushButton(tr("Snap again ({} undone)").format(len(self.skipped)))
            b.clicked.connect(self.redo_snaps)
            self.snap_box.addWidget(b)
            self.snap_buttons.append(b)

    def reinterpret(self, *_):
        if self.capture.strokes:
            self.interpret()

    def interpret(self):
        strokes, camera = self.capture.result()
        self.result = self.step = None
        self.preview.show(None)
        self._show_snaps(())
        if not strokes:
            self.text.setHtml(tr("<b>No strokes yet.</b> Draw over the model first."))
            return
        options = self.options()
        if loading():
            self.text.setHtml(
                tr("<i>Loading networks…</i> The reading follows when they are ready.")
            )
            self.text.repaint()  # the imports and predictor() below wait for the load
        from ...inference.context import InterpretError
        from ...inference.interpret import interpret
        from ...inference.session import SketchStep
        from ..make.make_model import FEATURE_OF_OPERATION

        try:
            solid = self._base_solid()
            networks = predictor()
            use_network_threads(networks)
            r = interpret(solid, strokes, camera, networks, options=options)
        except (InterpretError, ValueError, FileNotFoundError) as e:
            self.text.setHtml(
                f"<b style='color:#b00'>{tr('Not interpreted:')}</b> {e}<br>"
                + tr("Nothing was changed. Add or clear strokes and try again.")
            )
            return
        self.result, self.step = r, SketchStep(camera, strokes, options)
        probs = ", ".join(f"{k} {v:.0%}" for k, v in r.probabilities.items())
        lines = "".join(
            f"<li>{FEATURE_OF_OPERATION[op.type].reading(op)}</li>" for op in r.operations
        )
        other = ""
        if r.other_option is not None:  # a boss and a hole that draw the same lines
            other = (
                "<p>"
                + tr(
                    "The strokes read just as well as <b>{0}</b>: from this view "
                    "its primitive draws the same lines. Set Boolean to {0} if "
                    "that was meant."
                ).format(r.other_option.value)
                + "</p>"
            )
        if r.doubtful:
            other += f"<p style='color:#b60'><b>{tr('Warning:')}</b> {r.doubt()}.</p>"
        if r.unsnapped:
            other += f"<p>{tr('Not snapped:')} {r.unsnapped}.</p>"
        done = (
            tr("OK adds it to the model.")
            if self.feature is None
            else tr("OK applies it to {}.").format(self.feature.Label)
        )
        first = r.operations[0]
        kind = FEATURE_OF_OPERATION[first.type].kind_of(first)
        self.text.setHtml(
            f"<b>{tr('Read as')} {kind}</b> ({tr('operator')}: {probs})<ul>"
            f"{lines}</ul>{other}{r.timings_ms['total']:.0f} ms. {done}"
        )
        self.preview.show(to_part(r.solid))
        self._show_snaps(r.snaps)

    def sketch_json(self) -> str:
        """The strokes, view and choices of the current reading, as a session step."""
        from ...inference.session import step_to_dict

        return json.dumps(step_to_dict(self.step))

    def clear(self):
        self.capture.clear()
        self.skipped.clear()
        self._show_snaps(())
        self.result = self.step = None
        self.preview.show(None)
        self.text.clear()

    # ------------------------------------------------------------ closing

    def close(self, reset_edit: bool = True):
        """Take the capture and preview away and close the panel (and FreeCAD's edit mode
        of the edited step, unless FreeCAD is the one leaving it: `reset_edit` False)."""
        if self.closed:
            return
        self.closed = True
        self.preview.show(None)
        self.capture.remove()
        if self.shown is not None:  # the visibility from before the edit
            for o in self.model.Group:
                if o.Name in self.shown:
                    o.ViewObject.Visibility = self.shown[o.Name]
            self.model.Tip.ViewObject.Visibility = True
        FreeCADGui.Control.closeDialog()
        if (
            reset_edit
            and self.feature is not None
            and FreeCADGui.ActiveDocument.getInEdit() is not None
        ):
            FreeCADGui.ActiveDocument.resetEdit()

    def accept(self):
        if self.result is None:
            self.interpret()
            if self.result is None:
                return False  # stays open with the reason shown
        sketch = self.sketch_json()
        ops = list(self.result.operations)
        if self.feature is not None and len(ops) > 1 and self.model.Tip != self.feature:
            # a mirror image read with an edited step would go in the middle of the model
            error(
                tr("Cannot apply the edit"),
                tr("Only the last step can get a mirror image; set Mirror to none"),
            )
            return False
        name = tr("Sketch2CAD sketch") if self.feature is None else tr("Edit sketch step")
        try:
            with transaction(self.doc, name):
                # through the console, as Draft's tools do: each step lands in macros
                FreeCADGui.addModule(MAKE)
                FreeCADGui.addModule("Sketch2CADWorkbench.brep.protocol")
                if self.feature is not None:
                    FreeCADGui.doCommand(
                        replace_operation_command(self.feature, ops.pop(0), sketch)
                    )
                for op in ops:
                    FreeCADGui.doCommand(add_operation_command(self.model, op, sketch))
                FreeCADGui.doCommand(f"FreeCAD.getDocument({self.doc.Name!r}).recompute()")
        except Exception as e:  # the transaction was aborted: the document is as before
            error(tr("Cannot add the operation"), str(e))
            return False
        self.close()
        return True

    def reject(self):
        self.close()
        return True

    def cancel(self):
        self.reject()

    def getStandardButtons(self):
        flags = QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Cancel
        return int(getattr(flags, "value", flags))  # PySide6's flags are enums: int() fails
