# SPDX-License-Identifier: LGPL-2.1-or-later
"""GUI checks, run by test_addon_install.py: a user folder holding only a plain copy of the
repository in Mod (as the Addon Manager clones it), no dependencies. The first activation
offers the Install dialog; its Install button is pressed (as a user would, by a timer
while the dialog runs); the workbench then comes up whole, without a restart."""
import os
import sys
import time

sys.path.insert(0, os.path.join(os.environ["SKETCH2CAD_ROOT"], "tests", "freecad", "scripts"))
from harness import check, finish, run_checks, say  # noqa: E402

import FreeCAD  # noqa: E402
import FreeCADGui  # noqa: E402
from PySide import QtCore, QtGui  # noqa: E402

from Sketch2CADWorkbench.freecad_layer import dependencies  # noqa: E402

SEEN = {}


def app():
    return QtGui.QApplication.instance()


@check
def loaded_from_the_addon_folder_with_nothing_installed():
    import Sketch2CADWorkbench
    mod = os.path.join(FreeCAD.getUserAppDataDir(), "Mod")
    assert os.path.realpath(Sketch2CADWorkbench.__file__).startswith(os.path.realpath(mod))
    assert not os.path.exists(dependencies.folder()), dependencies.folder()
    assert "cadquery" in dependencies.missing()


def press_install_when_the_dialog_shows():
    dialog = app().activeModalWidget()
    if type(dialog).__name__ != "InstallDialog":
        QtCore.QTimer.singleShot(200, press_install_when_the_dialog_shows)
        return
    SEEN["text"] = dialog.info.text()
    SEEN["started"] = time.monotonic()
    dialog.install_button.click()
    SEEN["log_visible"] = dialog.log.isVisible()


@check
def first_activation_installs_through_the_dialog():
    QtCore.QTimer.singleShot(200, press_install_when_the_dialog_shows)
    FreeCADGui.activateWorkbench("Sketch2CADWorkbench")
    for _ in range(5):
        app().processEvents()
    say(f"INSTALL TOOK {time.monotonic() - SEEN['started']:.0f} s")
    assert "cadquery" in SEEN["text"] and dependencies.folder() in SEEN["text"], SEEN["text"]
    assert SEEN["log_visible"]
    assert os.path.isdir(dependencies.folder())
    assert not dependencies.missing(), dependencies.missing()


@check
def the_workbench_is_whole_without_a_restart():
    import cadquery
    assert cadquery.__file__.startswith(dependencies.folder()), cadquery.__file__
    from Sketch2CADWorkbench.commands import COMMANDS
    assert set(COMMANDS) <= set(FreeCADGui.listCommands())
    toolbar = FreeCADGui.getMainWindow().findChild(QtGui.QToolBar, "Sketch2CAD")
    assert toolbar is not None and toolbar.isVisible()
    FreeCAD.newDocument("addon")
    FreeCADGui.runCommand("Sketch2CAD_NewModel")
    for _ in range(5):
        app().processEvents()
    from Sketch2CADWorkbench.freecad_layer.make.make_model import find_models
    (model,) = find_models(FreeCAD.ActiveDocument)
    assert model.Tip.Shape.isValid() and model.Tip.Shape.Volume > 0


def main():
    finish(run_checks())


QtCore.QTimer.singleShot(0, main)
