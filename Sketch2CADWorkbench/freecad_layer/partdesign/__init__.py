# SPDX-License-Identifier: LGPL-2.1-or-later
"""A Sketch2CAD model as a PartDesign Body of FreeCAD's own features (convert.py), its
sketches fully constrained by the steps' parameters as named dimensions (sketches.py):
a file anyone can open, recompute and edit without the workbench."""
