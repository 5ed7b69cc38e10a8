# SPDX-License-Identifier: LGPL-2.1-or-later
"""The FreeCAD layer: the only code that imports FreeCAD (see tests/test_layering.py).

It is not called `freecad`: FreeCAD puts the Sketch2CADWorkbench folder on sys.path, so a
subpackage of that name would shadow FreeCAD's own `freecad` namespace package (which
loads namespace addons such as freecad.gears).
"""
