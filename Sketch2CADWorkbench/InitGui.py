# SPDX-License-Identifier: LGPL-2.1-or-later
# FreeCAD exec()s this file: no __file__, and top-level names are not visible inside
# methods, so everything is imported inside them. Init.py has already put the repository
# root and the venv at the front of sys.path; the commands (and cadquery) are imported
# only when the workbench is first activated.


class Sketch2CADWorkbench(Workbench):  # noqa: F821 (FreeCAD provides Workbench)
    """Sketch over the model; each sketch becomes an editable parametric feature."""

    MenuText = "Sketch2CAD"
    ToolTip = ("Sequential CAD modeling by sketching in context (extrude, bevel, add/subtract "
               "prism, sweep)")

    def __init__(self):
        from Sketch2CADWorkbench.freecad_layer.icons import icon_path
        self.__class__.Icon = icon_path("Sketch2CAD")

    def Initialize(self):
        import FreeCADGui
        from Sketch2CADWorkbench.commands import COMMANDS, MENU, TOOLBAR
        for name, command in COMMANDS.items():
            FreeCADGui.addCommand(name, command)
        self.appendToolbar("Sketch2CAD", TOOLBAR)
        self.appendMenu("Sketch2CAD", MENU)

    def GetClassName(self):
        return "Gui::PythonWorkbench"


Gui.addWorkbench(Sketch2CADWorkbench())  # noqa: F821
