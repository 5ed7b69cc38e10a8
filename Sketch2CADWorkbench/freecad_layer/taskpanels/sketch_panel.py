# SPDX-License-Identifier: LGPL-2.1-or-later
"""The Sketch task panel: strokes captured over the view, read by the interpret pipeline,
the reading and its preview shown (in the user's units), the designer's choices, accept
or discard. The same panel re-opens a sketched step (double-click in the tree): its
strokes are shown again in the view they were drawn in, and OK applies the new reading
to that step."""

import json
from dataclasses import dataclass, replace

import FreeCAD
import FreeCADGui
import numpy as np
from PySide import QtGui

from ...brep.protocol import AddSubPrism, EdgeSet, Mode, Operation, Sweep, operation_to_dict
from ..gui_helpers import error, transaction
from ..networks import loading, predictor, when_loaded
from ..preferences import regularize_default, snap_step, use_network_threads
from ..shapes import from_part, to_part
from ..trackers.preview import Preview
from ..trackers.stroke_capture import StrokeCapture
from ..trackers.view_camera import view_camera
from ..translate import translate

MAKE = "Sketch2CADWorkbench.freecad_layer.make.make_model"
# The Edges choice's entries, as the panel names them
EDGE_CHOICES = (
    ("drawn edge", EdgeSet.DRAWN),
    ("tangent chain", EdgeSet.CHAIN),
    ("whole outline", EdgeSet.OUTLINE),
)


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


@dataclass(frozen=True)
class Reading:
    """One reading of the strokes the panel offers: its operations (the operation, then
    its mirror image if asked) and the solid they make."""

    operations: tuple
    solid: object  # cq.Solid


def _empty(layout) -> None:
    """Take every widget out of `layout` (they are deleted)."""
    while layout.count():
        w = layout.takeAt(0).widget()
        if w is not None:
            w.deleteLater()


def _other_boolean(op: Operation) -> Operation | None:
    """A primitive added or subtracted with its Boolean flipped, to name the other
    reading; None for any other operation."""
    if not isinstance(op, (AddSubPrism, Sweep)) or op.mode.flipped is None:
        return None
    return replace(op, mode=op.mode.flipped)


def _shrinkable(button) -> None:
    """Let a button be narrower than its label (Qt elides nothing, but the panel's width
    then follows the Tasks area, not the longest label). FreeCAD 1.1's theme overrides
    this with its QPushButton min-width: there only short labels keep the panel narrow
    (regularize.SNAP_KINDS)."""
    button.setSizePolicy(QtGui.QSizePolicy.Ignored, QtGui.QSizePolicy.Fixed)
    button.setMinimumWidth(40)


# The values of an operation (its JSON keys) as the panel names them.
VALUE_NAMES = {
    "type": "operator",
    "face": "base face",
    "d": "length",
    "polygon": "vertices",
    "mode": "Boolean",
    "center": "centre",
    "r0": "radius",
    "r1": "far radius",
    "profile": "profile",
    "corner": "corner",
    "opposite": "edge end",
}


def _changed_values(now: dict, new: dict, tol: float = 1e-4) -> list:
    """The names (VALUE_NAMES) of the values of operation `new` that differ from `now`'s
    (both as JSON objects; numbers within `tol` mm or of a unit normal are the same; a
    base face is the same when its plane is: its point is any point inside it)."""
    for op in (now, new):
        if "face" in op:
            f = dict(op["face"])
            f["point"] = float(np.dot(f.pop("point"), f["normal"]))
            op["face"] = f

    def same(a, b) -> bool:
        if isinstance(a, dict) and isinstance(b, dict):
            return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
        if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
            return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b, strict=False))
        if isinstance(a, (int, float)) and isinstance(b, (int, float)):
            return abs(a - b) <= tol * max(1.0, abs(a), abs(b))
        return a == b

    keys = list(now) + [k for k in new if k not in now]
    return [VALUE_NAMES.get(k, k) for k in keys if not same(now.get(k), new.get(k))]


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
        self.readings, self.chosen = [], 0  # the readings offered, the one chosen
        self.reading_buttons = []
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
        # a bevel's edge set: the edge its profile is drawn across, the chain continuing
        # it, or the whole outline of its face (InterpretOptions.edges)
        self.edges = QtGui.QComboBox()
        for label, edges in EDGE_CHOICES:
            self.edges.addItem(tr(label), edges.value)
        form = QtGui.QFormLayout()
        # labels above their fields when the panel is narrow (FreeCAD's default combo view)
        form.setRowWrapPolicy(QtGui.QFormLayout.WrapLongRows)
        form.addRow(tr("Boolean"), self.option)
        form.addRow(tr("Mirror"), self.symmetry)
        self.symmetry.setToolTip(
            tr("Also add the mirror image through the model's mid-plane normal to this axis")
        )
        form.addRow(tr("Edges"), self.edges)
        self.edges.setToolTip(
            tr(
                "A round or chamfer drawn across an edge follows that edge, the edges "
                "continuing it without a kink, or the whole outline of its face"
            )
        )
        lay.addLayout(form)
        lay.addWidget(self.regularize)
        buttons = QtGui.QHBoxLayout()
        self.interpret_button = QtGui.QPushButton(tr("Interpret"))
        self.clear_button = QtGui.QPushButton(tr("Clear strokes"))
        buttons.addWidget(self.interpret_button)
        buttons.addWidget(self.clear_button)
        lay.addLayout(buttons)
        # a reading far from its strokes (a scribble) is added only when asked for (near
        # the top, above the readings' row: seen without scrolling in FreeCAD 1.1's
        # overlay panel on a 768 px high screen)
        self.anyway_button = QtGui.QPushButton(tr("Add anyway"))
        self.anyway_button.setToolTip(
            tr("Add this reading although its strokes lie far from it (OK does not)")
        )
        self.anyway_button.hide()
        self.anyway_button.clicked.connect(self.accept_anyway)
        lay.addWidget(self.anyway_button)
        # the readings that draw the same strokes (a boss and a hole, paper Fig. 5b):
        # one checkable button each, the checked one previewed and added by OK
        self.reading_box = QtGui.QHBoxLayout()
        lay.addLayout(self.reading_box)
        # one short button per snap the reading applied (what moved to what in its
        # tooltip): a click reads the strokes again without it
        # (InterpretOptions.skip_snaps); undone snaps stay off until cleared
        self.snap_box = QtGui.QGridLayout()
        lay.addLayout(self.snap_box)
        self.text = QtGui.QTextEdit()
        self.text.setReadOnly(True)
        self.text.setMinimumWidth(0)
        # the reading without scrolling most of the time, within a 768 px high screen
        self.text.setMinimumHeight(150)
        lay.addWidget(self.text)
        for widget in (self.option, self.symmetry, self.edges):
            # combo boxes size to their longest entry by default
            widget.setSizeAdjustPolicy(QtGui.QComboBox.AdjustToMinimumContentsLengthWithIcon)
            widget.setMinimumContentsLength(6)
        self.interpret_button.clicked.connect(self.interpret)
        self.clear_button.clicked.connect(self.clear)
        for box in (self.option, self.symmetry, self.edges):
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
            # shown where the step is now when an edit of an earlier step moved it
            shift = step.camera.image_of(tuple(getattr(obj, "SketchOffset", (0, 0, 0))))
            self.capture.strokes = [
                list(step.camera.unproject(s + shift, depth)) for s in step.strokes
            ]
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
            self.edges.blockSignals(True)
            self.edges.setCurrentIndex(self.edges.findData(c.edges.value))
            self.edges.blockSignals(False)
        # the solid before this step, as PartDesign shows while a feature is edited; the
        # view providers' switches, not their Visibility, which would mark the document
        # modified for an edit that may be cancelled. Every step's view provider is the
        # same, so the visible Tip's switch child is the base's display mode too.
        self.shown = {
            o.Name: o.ViewObject.SwitchNode.whichChild.getValue() for o in self.model.Group
        }
        mode = max([0, *self.shown.values()])
        for o in self.model.Group:
            o.ViewObject.SwitchNode.whichChild = mode if o == obj.Base else -1
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
            snap_step=snap_step(view_camera(self.view).pixel_size),
            skip_snaps=frozenset(self.skipped),
            edges=EdgeSet(self.edges.currentData()),
        )

    def undo_snap(self, key: str) -> None:
        """Read the strokes again without the snap `key` (a SNAP_KINDS key)."""
        self.skipped.add(key)
        self.reinterpret()

    def redo_snaps(self) -> None:
        self.skipped.clear()
        self.reinterpret()

    def _show_snaps(self, snaps) -> None:
        """A short button per applied snap (its undo; the snap in its tooltip), and one to
        snap again what was undone, two to a row: the panel stays as narrow as the Tasks
        area."""
        from ...inference.fitting.regularize import SNAP_KINDS

        _empty(self.snap_box)
        self.snap_buttons = []
        # one button per kind: an undo reads the strokes again without every snap of it
        kinds: dict[str, list] = {}
        for snap in snaps:
            kinds.setdefault(snap.key, []).append(snap)
        for key, of_kind in kinds.items():
            b = QtGui.QPushButton(SNAP_KINDS[key])
            b.setToolTip(
                tr("Read the strokes again without this snap: {}").format(
                    "; ".join(snap.describe() for snap in of_kind)
                )
            )
            b.clicked.connect(lambda _=False, k=key: self.undo_snap(k))
            self.snap_buttons.append(b)
        if self.skipped:
            b = QtGui.QPushButton(tr("Snap again"))
            b.setToolTip(
                tr("Read the strokes again with the {} undone snaps").format(len(self.skipped))
            )
            b.clicked.connect(self.redo_snaps)
            self.snap_buttons.append(b)
        if snaps:
            self.snap_box.addWidget(QtGui.QLabel(tr("Undo a snap:")), 0, 0, 1, 2)
        for i, b in enumerate(self.snap_buttons):
            _shrinkable(b)
            self.snap_box.addWidget(b, 1 + i // 2, i % 2)

    def reinterpret(self, *_):
        if self.capture.strokes:
            self.interpret()

    def _readings(self, r) -> list:
        """The readings to choose from: the interpretation's, and its alternative's when
        the other Boolean's reading explains the strokes too and builds
        (`Interpretation.alternative`, fitted with that Boolean: a hole's rim where the
        boss read has its top)."""
        readings = [Reading(r.operations, r.solid)]
        if r.alternative is not None:
            readings.append(Reading(r.alternative.operations, r.alternative.solid))
        return readings

    def _show_readings(self) -> None:
        """One checkable button per reading when there are several (the checked one is
        previewed, described and added by OK). A primitive read alone gets a button for
        its other Boolean too: a hole read as a boss, or a boss as a hole, is always one
        click from the reading meant (`read_as`)."""
        from ..make.make_model import FEATURE_OF_OPERATION

        _empty(self.reading_box)
        self.reading_buttons = []
        ops = [reading.operations[0] for reading in self.readings]
        other = _other_boolean(ops[0]) if len(ops) == 1 else None
        if len(ops) < 2 and other is None:
            return
        self.reading_box.addWidget(QtGui.QLabel(tr("Reads as:")))
        for i, op in enumerate([*ops, *([other] if other else [])]):
            cls = FEATURE_OF_OPERATION[op.type]
            b = QtGui.QPushButton(cls.kind_of(op))
            b.setCheckable(True)
            b.setChecked(i == self.chosen)
            if i < len(ops):
                b.setToolTip(tr("Preview and add this reading: {}").format(cls.reading(op)))
                b.clicked.connect(lambda _=False, k=i: self.choose(k))
            else:
                b.setToolTip(
                    tr("Read the strokes as a {} (the Boolean {})").format(
                        cls.kind_of(op), op.mode.value
                    )
                )
                b.clicked.connect(lambda _=False, m=op.mode: self.read_as(m))
            _shrinkable(b)
            self.reading_box.addWidget(b)
            self.reading_buttons.append(b)

    def choose(self, index: int) -> None:
        """Preview reading `index` of `readings`; OK adds that one."""
        self.chosen = index
        for i, b in enumerate(self.reading_buttons):
            b.setChecked(i == index)
        self._describe()
        self.preview.show(to_part(self.readings[index].solid))

    def interpret(self):
        self._show_result(None, None)
        if not self.capture.result()[0]:
            self.text.setHtml(tr("<b>No strokes yet.</b> Draw over the model first."))
            return
        r, step, why = self._read(self.options())
        if r is None:
            self.text.setHtml(
                f"<b style='color:#b00'>{tr('Not interpreted:')}</b> {why}<br>"
                + tr("Nothing was changed. Add or clear strokes and try again.")
            )
            return
        self._show_result(r, step)

    def read_as(self, mode: Mode) -> None:
        """Read the strokes with the Boolean `mode` chosen, as choosing it in the Boolean
        box does; where no reading of it builds, the reading shown stays, with the reason."""
        r, step, why = self._read(replace(self.options(), option=mode))
        if r is None:
            self._show_readings()  # the clicked button unchecked again
            self.text.append(
                f"<p style='color:#b00'><b>{tr('Not read as {}:').format(mode.value)}</b> "
                f"{why}. {tr('The reading above stays.')}</p>"
            )
            return
        self.option.blockSignals(True)  # read already: no second reading
        self.option.setCurrentIndex(self.option.findText(mode.value))
        self.option.blockSignals(False)
        self._show_result(r, step)

    def _read(self, options) -> tuple:
        """The strokes drawn read on the base solid with `options`
        (inference.interpret): the interpretation and the SketchStep it was read from,
        and "", or None, None and why they were not read."""
        if loading():
            self.text.setHtml(
                tr("<i>Loading networks…</i> The reading follows when they are ready.")
            )
            self.text.repaint()  # the imports and predictor() below wait for the load
        from ...inference.context import InterpretError
        from ...inference.interpret import interpret
        from ...inference.session import SketchStep

        strokes, camera = self.capture.result()
        try:
            solid = self._base_solid()
            networks = predictor()
            use_network_threads(networks)
            r = interpret(solid, strokes, camera, networks, options=options)
        except (InterpretError, ValueError, FileNotFoundError) as e:
            return None, None, str(e)
        return r, SketchStep(camera, strokes, options), ""

    def _show_result(self, r, step) -> None:
        """Show the interpretation `r` read from `step` (None: nothing read)."""
        self.result, self.step = r, step
        self.readings = [] if r is None else self._readings(r)
        self.chosen = 0
        self._show_readings()
        self.anyway_button.setVisible(r is not None and r.doubtful)
        self._show_snaps(() if r is None else r.snaps)
        self.preview.show(None if r is None else to_part(r.solid))
        if r is not None:
            self._describe()

    def _describe(self) -> None:
        """The chosen reading in words, the warnings, and what OK does."""
        from ..make.make_model import FEATURE_OF_OPERATION

        r, ops = self.result, self.readings[self.chosen].operations
        probs = ", ".join(f"{k} {v:.0%}" for k, v in r.classified.items())
        if r.shell_by_rim:
            probs += "; " + tr("shell: the strokes close into a rim")
        lines = "".join(f"<li>{FEATURE_OF_OPERATION[op.type].reading(op)}</li>" for op in ops)
        other = ""
        if len(self.readings) > 1:  # a boss and a hole that draw the same lines
            other = (
                "<p>"
                + tr(
                    "The strokes read just as well as another Boolean: from this view "
                    "both primitives draw the same lines. Pick the one meant above."
                )
                + "</p>"
            )
        if r.doubtful:
            other += f"<p style='color:#b60'><b>{tr('Warning:')}</b> {r.doubt()}.</p>"
        if r.unsnapped:
            other += f"<p>{tr('Not snapped:')} {r.unsnapped}.</p>"
        if r.doubtful:
            done = tr("OK does not add a reading this far from its strokes: Add anyway does.")
        elif self.feature is None:
            done = tr("OK adds it to the model.")
        else:
            done = self._change_of_edit(ops[0])
        first = ops[0]
        kind = FEATURE_OF_OPERATION[first.type].kind_of(first)
        self.text.setHtml(
            f"<b>{tr('Read as')} {kind}</b> ({tr('operator')}: {probs})<ul>"
            f"{lines}</ul>{other}{r.timings_ms['total']:.0f} ms. {done}"
        )

    def _change_of_edit(self, op) -> str:
        """What OK would change in the edited step: its values that differ from `op`."""
        from ..make.make_model import FEATURE_OF_OPERATION

        obj = self.feature
        try:
            now = obj.Proxy.operation(obj)
        except (ValueError, TypeError, AttributeError):
            return tr("OK applies it to {}.").format(obj.Label)
        changed = _changed_values(now.to_dict(), op.to_dict())
        if not changed:
            return tr("OK keeps {} as it is: the strokes read as its current values.").format(
                obj.Label
            )
        return (
            "<p><b>"
            + tr("OK changes {0}'s {1}.").format(obj.Label, ", ".join(changed))
            + "</b> "
            + tr("Now: {}.").format(FEATURE_OF_OPERATION[now.type].reading(now))
            + "</p>"
        )

    def sketch_json(self) -> str:
        """The strokes, view and choices of the current reading, as a session step."""
        from ...inference.session import step_to_dict

        return json.dumps(step_to_dict(self.step))

    def clear(self):
        self.capture.clear()
        self.skipped.clear()
        self._show_result(None, None)
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
        if self.shown is not None:  # what was shown before the edit
            for o in self.model.Group:
                if o.Name in self.shown:
                    o.ViewObject.SwitchNode.whichChild = self.shown[o.Name]
        FreeCADGui.Control.closeDialog()
        if (
            reset_edit
            and self.feature is not None
            and FreeCADGui.ActiveDocument.getInEdit() is not None
        ):
            FreeCADGui.ActiveDocument.resetEdit()

    def accept_anyway(self) -> None:
        """Add the reading although it is doubtful (OK refuses to)."""
        self.accept(anyway=True)  # closes the panel when it adds

    def accept(self, anyway: bool = False):
        if self.result is None:
            self.interpret()
            if self.result is None:
                return False  # stays open with the reason shown
        if self.result.doubtful and not anyway:
            self.text.append(
                "<p style='color:#b00'><b>"
                + tr("Not added:")
                + "</b> "
                + tr(
                    "the strokes lie far from this reading. Press Add anyway to add it, "
                    "or clear the strokes and draw again."
                )
                + "</p>"
            )
            return False  # stays open
        if self.chosen:  # another Boolean picked: the step records it as chosen
            mode = self.readings[self.chosen].operations[0].mode
            self.step = replace(self.step, choices=replace(self.step.choices, option=mode))
        sketch = self.sketch_json()
        ops = list(self.readings[self.chosen].operations)
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
