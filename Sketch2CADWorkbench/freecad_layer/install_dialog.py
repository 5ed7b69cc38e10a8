# SPDX-License-Identifier: LGPL-2.1-or-later
"""The dialog that installs the workbench's Python dependencies from inside FreeCAD, and
its command. Imports only FreeCAD, Qt and the standard library: it runs when cadquery,
torch and VTK are not there yet.
"""

import queue
import threading

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from . import dependencies, env
from .icons import icon_path

COMMAND = "Sketch2CAD_InstallDependencies"


def _exec(dialog) -> int:
    return dialog.exec() if hasattr(dialog, "exec") else dialog.exec_()  # PySide6 / PySide2


class InstallDialog(QtGui.QDialog):
    """Says what is missing and where it goes; Install runs `dependencies.install` in a
    thread and shows pip's lines as they come; the FreeCAD window stays responsive."""

    def __init__(self, plan: dependencies.InstallPlan, missing: list, parent=None):
        super().__init__(parent)
        self.plan = plan
        self.lines = queue.Queue()
        self.outcome = None  # None while running, else "" (done) or the error's text
        self.setWindowTitle("Sketch2CAD: install Python packages")
        lay = QtGui.QVBoxLayout(self)
        torch = (
            "torch is already on this system."
            if plan.skipped
            else f"torch comes as a CPU build from {plan.torch_index}."
            if plan.torch_index
            else ""
        )
        self.info = QtGui.QLabel(
            f"Sketch2CAD needs Python packages that FreeCAD does not include: "
            f"<b>{', '.join(missing)}</b>.<br>Install them now with FreeCAD's Python "
            f"(<tt>{plan.python}</tt>) into <tt>{plan.target}</tt>? They take about 3 GB "
            f"and a few minutes to download. {torch}<br>Nothing else in FreeCAD changes."
        )
        self.info.setWordWrap(True)
        self.info.setTextInteractionFlags(QtCore.Qt.TextSelectableByMouse)
        lay.addWidget(self.info)
        self.progress = QtGui.QProgressBar()
        self.progress.setRange(0, 0)  # busy: pip does not say how much is left
        self.progress.hide()
        lay.addWidget(self.progress)
        self.log = QtGui.QPlainTextEdit()
        self.log.setReadOnly(True)
        self.log.hide()
        lay.addWidget(self.log)
        row = QtGui.QHBoxLayout()
        row.addStretch(1)
        self.install_button = QtGui.QPushButton("Install")
        self.close_button = QtGui.QPushButton("Not now")
        row.addWidget(self.install_button)
        row.addWidget(self.close_button)
        lay.addLayout(row)
        self.install_button.clicked.connect(self.start)
        self.close_button.clicked.connect(self.reject)
        self.timer = QtCore.QTimer(self)
        self.timer.timeout.connect(self._poll)
        self.resize(640, 200)

    def start(self):
        self.install_button.setEnabled(False)
        self.close_button.setEnabled(False)
        self.progress.show()
        self.log.show()
        self.resize(640, 420)
        threading.Thread(target=self._work, daemon=True).start()
        self.timer.start(100)

    def _work(self):
        try:
            dependencies.install(self.plan, on_line=self.lines.put)
            self.outcome = ""
        except (dependencies.InstallError, OSError) as e:
            self.outcome = str(e) or type(e).__name__

    def _poll(self):
        while not self.lines.empty():
            line = self.lines.get()
            self.log.appendPlainText(line)
            FreeCAD.Console.PrintLog(f"Sketch2CAD install: {line}\n")
        if self.outcome is None:
            return
        self.timer.stop()
        self.progress.setRange(0, 1)
        self.progress.setValue(1 if not self.outcome else 0)
        if self.outcome:
            self.info.setText(
                "<b style='color:#b00'>The installation failed</b>; FreeCAD and "
                "any earlier installation are unchanged. pip said:"
            )
            self.log.appendPlainText(self.outcome)
            self.close_button.setText("Close")
            self.close_button.setEnabled(True)
            FreeCAD.Console.PrintError(
                f"Sketch2CAD: installing the dependencies failed: {self.outcome}\n"
            )
            return
        FreeCAD.Console.PrintMessage(
            f"Sketch2CAD: dependencies installed into {self.plan.target}\n"
        )
        self.accept()


def offer(missing: list) -> bool:
    """Show the dialog for `missing`; True when they are importable afterwards (installed
    and put on sys.path). Declined or failed: the report view says what to run by hand."""
    try:
        plan = dependencies.user_plan()
    except dependencies.InstallError as e:
        FreeCAD.Console.PrintError(f"Sketch2CAD needs {', '.join(missing)}: {e}\n")
        return False
    dialog = InstallDialog(plan, missing, FreeCADGui.getMainWindow())
    if _exec(dialog) and not dialog.outcome:
        env.bootstrap()
        shadowed = env.shadowed_modules()
        if shadowed:
            FreeCAD.Console.PrintWarning(
                f"Sketch2CAD: {', '.join(shadowed)} {'was' if len(shadowed) == 1 else 'were'} "
                "loaded by FreeCAD before the installation; restart FreeCAD to use the "
                "installed copy\n"
            )
        return not dependencies.missing()
    FreeCAD.Console.PrintWarning(
        f"Sketch2CAD needs {', '.join(missing)}. Install them from the menu Sketch2CAD > "
        f"Install dependencies, or run: {dependencies.manual_command(plan)}\n"
    )
    return False


class InstallDependencies:
    """The command behind the menu entry, for a user who declined at first."""

    def __init__(self, on_installed=None):
        self.on_installed = on_installed

    def GetResources(self):
        return {
            "Pixmap": icon_path("Sketch2CAD"),
            "MenuText": "Install dependencies",
            "ToolTip": "Install the Python packages Sketch2CAD needs (cadquery, torch, "
            "VTK, ...) with FreeCAD's Python",
        }

    def IsActive(self):
        return True

    def Activated(self):
        missing = dependencies.missing()
        if not missing:
            QtGui.QMessageBox.information(
                FreeCADGui.getMainWindow(),
                "Sketch2CAD",
                "Every package Sketch2CAD needs is installed.",
            )
            return
        if offer(missing) and self.on_installed:
            self.on_installed()
