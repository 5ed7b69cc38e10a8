# SPDX-License-Identifier: LGPL-2.1-or-later
# FreeCAD exec()s this file at startup, in the GUI and in freecadcmd, before any workbench
# is activated or any document restored. It puts the repository root (the parent of this
# folder, which FreeCAD put on sys.path) and the workbench's dependency folder, when it has
# been installed, at the front of sys.path, so that the proxies of saved Sketch2CAD
# documents and the workbench import cadquery with that folder's numpy and pyparsing.
# When the folder is missing nothing fails here: the workbench offers to install it when
# it is first activated. There is no __file__ here.


def _sketch2cad_bootstrap():
    import os
    import sys

    here = next(
        p
        for p in sys.path
        if os.path.basename(os.path.normpath(p)) == "Sketch2CADWorkbench"
        and os.path.isfile(os.path.join(p, "Init.py"))
    )
    root = os.path.dirname(os.path.normpath(here))
    if root not in sys.path:
        sys.path.insert(0, root)
    from Sketch2CADWorkbench.freecad_layer import env

    env.bootstrap()


_sketch2cad_bootstrap()
del _sketch2cad_bootstrap
