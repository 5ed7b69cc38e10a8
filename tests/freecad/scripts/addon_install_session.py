# SPDX-License-Identifier: LGPL-2.1-or-later
"""GUI checks, run by test_addon_install.py: a user folder holding only a plain copy of the
repository in Mod (as the Addon Manager clones it), no dependencies. The first activation
offers the Install dialog; the user says Not now, and FreeCAD goes on with the workbench
holding its Install command and the report view saying what to run by hand. That command
shows the dialog again; its Install button is pressed (buttons are pressed as a user
would, by a timer while the dialog runs); the workbench then comes up whole, without a
restart."""

import os
import sys
import time

sys.path.insert(0, os.path.join(os.environ["SKETCH2CAD_ROOT"], "tests", "freecad", "scripts"))
import FreeCAD
import FreeCADGui
from harness import check, finish, run_checks, say
from PySide import QtCore, QtGui

from Sketch2CADWorkbench.freecad_layer import dependencies

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


def press_when_the_dialog_shows(button: str):
    dialog = app().activeModalWidget()
    if type(dialog).__name__ != "InstallDialog":
        QtCore.QTimer.singleShot(200, lambda: press_when_the_dialog_shows(button))
        return
    SEEN["text"] = dialog.info.text()
    SEEN["started"] = time.monotonic()
    getattr(dialog, button).click()
    SEEN["log_visible"] = dialog.log.isVisible()


def settle():
    for _ in range(5):
        app().processEvents()


def report_view() -> str:
    return FreeCADGui.getMainWindow().findChild(QtGui.QTextEdit, "Report view").toPlainText()


def toolbar_actions() -> list:
    toolbar = FreeCADGui.getMainWindow().findChild(QtGui.QToolBar, "Sketch2CAD")
    return (
        [a.text() for a in toolbar.actions() if a.isVisible() and not a.isSeparator()]
        if toolbar is not None and toolbar.isVisible()
        else []
    )


@check
def declined_at_first_activation_freecad_goes_on_and_says_what_to_run():
    QtCore.QTimer.singleShot(200, lambda: press_when_the_dialog_shows("close_button"))
    FreeCADGui.activateWorkbench("Sketch2CADWorkbench")
    settle()
    assert FreeCADGui.activeWorkbench().name() == "Sketch2CADWorkbench"
    assert "cadquery" in SEEN["text"] and dependencies.folder() in SEEN["text"], SEEN["text"]
    assert not os.path.exists(dependencies.folder())
    assert toolbar_actions() == ["Install dependencies"], toolbar_actions()
    said = report_view()
    assert "Sketch2CAD needs" in said and "-m pip install" in said, said
    assert f"--target {dependencies.folder()}" in said, said
    assert "Sketch2CAD_NewModel" not in FreeCADGui.listCommands()


@check
def the_install_command_installs_through_the_dialog():
    QtCore.QTimer.singleShot(200, lambda: press_when_the_dialog_shows("install_button"))
    FreeCADGui.runCommand("Sketch2CAD_InstallDependencies")
    settle()
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
    assert "New model" in toolbar_actions() and "Sketch an operation" in toolbar_actions()
    FreeCAD.newDocument("addon")
    FreeCADGui.runCommand("Sketch2CAD_NewModel")
    for _ in range(5):
        app().processEvents()
    from Sketch2CADWorkbench.freecad_layer.queries import find_models

    (model,) = find_models(FreeCAD.ActiveDocument)
    assert model.Tip.Shape.isValid() and model.Tip.Shape.Volume > 0


def main():
    finish(run_checks())


QtCore.QTimer.singleShot(0, main)
