# SPDX-License-Identifier: LGPL-2.1-or-later
# FreeCAD exec()s this file: no __file__, and top-level names are not visible inside
# methods, so everything is imported inside them. Init.py has already put the repository
# root and the dependency folder (when installed) at the front of sys.path; the commands
# are imported when the workbench is first activated (without cadquery, which they import
# on first use), and each activation starts loading the networks in the background
# (freecad_layer/networks.py) unless they are loaded or loading. When cadquery,
# torch or VTK are missing then, a dialog offers to install them (see
# freecad_layer/install_dialog.py); declined, the workbench holds only its Install command.


class Sketch2CADWorkbench(Workbench):  # noqa: F821 (FreeCAD provides Workbench)
    """Sketch over the model; each sketch becomes an editable parametric feature."""

    MenuText = "Sketch2CAD"
    ToolTip = (
        "Sequential CAD modeling by sketching in context (extrude, bevel, add/subtract "
        "prism, sweep)"
    )

    def __init__(self):
        from Sketch2CADWorkbench.freecad_layer.icons import icon_path

        self.__class__.Icon = icon_path("Sketch2CAD")

    def Initialize(self):
        import FreeCADGui

        from Sketch2CADWorkbench.freecad_layer import dependencies, install_dialog, preferences

        preferences.add_page()
        FreeCADGui.addCommand(
            install_dialog.COMMAND, install_dialog.InstallDependencies(self.installed_later)
        )
        missing = dependencies.missing()
        if missing and not install_dialog.offer(missing):
            self.appendMenu("Sketch2CAD", [install_dialog.COMMAND])
            self.appendToolbar("Sketch2CAD", [install_dialog.COMMAND])
            return
        self.add_commands()

    def Activated(self):
        from PySide import QtCore

        from Sketch2CADWorkbench.freecad_layer import networks

        if getattr(self, "complete", False):
            # once FreeCAD has finished switching: the thread would slow the switch down
            QtCore.QTimer.singleShot(0, networks.load_in_background)

    def add_commands(self):
        """Register the commands and fill the toolbar and menu."""
        import FreeCADGui

        from Sketch2CADWorkbench.commands import COMMANDS, MENU, TOOLBAR

        for name, command in COMMANDS.items():
            if name not in FreeCADGui.listCommands():
                FreeCADGui.addCommand(name, command)
        self.removeToolbar("Sketch2CAD")
        self.removeMenu("Sketch2CAD")
        self.appendToolbar("Sketch2CAD", TOOLBAR)
        self.appendMenu("Sketch2CAD", MENU + ["Separator", "Sketch2CAD_InstallDependencies"])
        self.complete = True  # the dependencies are there: Activated may load the networks

    def installed_later(self):
        """After the Install command succeeded: the full workbench, shown at once."""
        import FreeCADGui

        self.add_commands()
        FreeCADGui.activateWorkbench("NoneWorkbench")  # toolbars are rebuilt on activation
        FreeCADGui.activateWorkbench("Sketch2CADWorkbench")

    def GetClassName(self):
        return "Gui::PythonWorkbench"


Gui.addWorkbench(Sketch2CADWorkbench())  # noqa: F821
