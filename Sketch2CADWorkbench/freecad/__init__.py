# SPDX-License-Identifier: LGPL-2.1-or-later
"""The FreeCAD layer: the only code that imports FreeCAD (see tests/test_layering.py)."""
