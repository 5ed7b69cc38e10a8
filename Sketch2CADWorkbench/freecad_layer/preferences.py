# SPDX-License-Identifier: LGPL-2.1-or-later
"""Sketch2CAD's page in Edit > Preferences, and the values it sets, as the workbench reads
them (FreeCAD's parameters at User parameter:BaseApp/Preferences/Mod/Sketch2CAD).

- Regularize: the Sketch panel's "Regularize" box when it opens (the paper's snapping and
  rectification).
- SnapStep: lengths read from a sketch (a pad's offset, a prism's length, a revolution's
  radii and height) are rounded to this step when regularizing; 0 keeps them as fitted;
  AUTOMATIC (the default) takes the unit schema's grid (units.length_grid).
- DependencyFolder: where the Install command puts cadquery, torch and VTK
  (dependencies.folder(); read when FreeCAD starts).
- NetworkThreads: the CPU threads the networks use; 0 leaves the predictor's default.
"""

import FreeCAD

from .dependencies import PARAMETERS
from .translate import QT_TRANSLATE_NOOP, translate
from .units import length_grid

PAGE = QT_TRANSLATE_NOOP("QObject", "Sketch2CAD")


def parameters():
    return FreeCAD.ParamGet(PARAMETERS)


def regularize_default() -> bool:
    return parameters().GetBool("Regularize", True)


AUTOMATIC = -1.0  # SnapStep: the unit schema's grid


def snap_step(pixel_mm: float) -> float:
    """The snapping step for lengths, mm (0: none), in a view of `pixel_mm` mm per pixel:
    the one chosen in the preferences, else the unit schema's (units.length_grid)."""
    step = parameters().GetFloat("SnapStep", AUTOMATIC)
    return length_grid(pixel_mm) if step < 0 else step


def network_threads() -> int:
    """CPU threads for the networks (0: the predictor's own default)."""
    return max(0, parameters().GetInt("NetworkThreads", 0))


def use_network_threads(predictor) -> None:
    """Give the predictor (inference.weights.NetworkPredictor) the thread count the user
    chose; with 0 it keeps the count it was loaded with."""
    n = network_threads()
    if n:
        predictor.threads = n


class PreferencesPage:
    """The page FreeCAD shows under Edit > Preferences > Sketch2CAD (a Python page:
    FreeCAD builds it without arguments and calls loadSettings / saveSettings)."""

    def __init__(self):
        from PySide import QtGui

        self.form = QtGui.QWidget()
        self.form.setObjectName("Sketch2CADPreferences")
        self.form.setWindowTitle(translate("Sketch2CAD", "Sketch2CAD"))
        lay = QtGui.QFormLayout(self.form)
        self.regularize = QtGui.QCheckBox(translate("Sketch2CAD", "Regularize sketches"))
        self.regularize.setToolTip(
            translate(
                "Sketch2CAD",
                "Snap and rectify what is read from a sketch (the Sketch panel's initial choice)",
            )
        )
        lay.addRow(self.regularize)
        self.snap = QtGui.QDoubleSpinBox()
        self.snap.setRange(AUTOMATIC, 100.0)
        self.snap.setDecimals(3)
        self.snap.setSuffix(" mm")
        self.snap.setSpecialValueText(translate("Sketch2CAD", "from the unit schema"))
        self.snap.setToolTip(
            translate(
                "Sketch2CAD",
                "Round lengths read from a sketch to this step when regularizing "
                "(0: keep them as fitted; lowest: the unit schema's grid, 1 mm in mm "
                "schemas, 0.5 mm where the strokes are that precise)",
            )
        )
        lay.addRow(translate("Sketch2CAD", "Snapping step"), self.snap)
        self.folder = QtGui.QLineEdit()
        self.folder.setToolTip(
            translate(
                "Sketch2CAD",
                "Where cadquery, torch and VTK are installed (empty: the default "
                "folder); takes effect when FreeCAD restarts",
            )
        )
        lay.addRow(translate("Sketch2CAD", "Dependency folder"), self.folder)
        self.threads = QtGui.QSpinBox()
        self.threads.setRange(0, 256)
        self.threads.setSpecialValueText(translate("Sketch2CAD", "automatic"))
        self.threads.setToolTip(
            translate(
                "Sketch2CAD", "CPU threads the networks use (automatic: the workbench's default)"
            )
        )
        lay.addRow(translate("Sketch2CAD", "Networks' threads"), self.threads)

    def loadSettings(self):
        p = parameters()
        self.regularize.setChecked(regularize_default())
        self.snap.setValue(max(AUTOMATIC, p.GetFloat("SnapStep", AUTOMATIC)))
        self.folder.setText(p.GetString("DependencyFolder", ""))
        self.threads.setValue(network_threads())

    def saveSettings(self):
        p = parameters()
        p.SetBool("Regularize", self.regularize.isChecked())
        p.SetFloat("SnapStep", float(self.snap.value()))
        p.SetString("DependencyFolder", self.folder.text().strip())
        p.SetInt("NetworkThreads", int(self.threads.value()))


def add_page() -> None:
    """Register the page (once per FreeCAD session)."""
    import FreeCADGui

    from .icons import ICONS

    FreeCADGui.addIconPath(ICONS)  # the page's group icon: preferences-sketch2cad.svg
    FreeCADGui.addPreferencePage(PreferencesPage, PAGE)
