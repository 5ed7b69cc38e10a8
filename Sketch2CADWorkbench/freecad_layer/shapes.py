# SPDX-License-Identifier: LGPL-2.1-or-later
"""Shapes crossing between cadquery's OCCT and FreeCAD's OCCT, as BREP text.

cadquery is imported on the first crossing, not with this module: the feature classes and
the commands import it when the workbench is activated, which must stay fast (importing
cadquery takes seconds; networks.py preloads it in the background meanwhile).
"""

import FreeCAD  # noqa: F401  (Part needs FreeCAD imported first)
import Part


def to_part(shape) -> "Part.Shape":
    """A cadquery shape as a FreeCAD Part.Shape."""
    from ..brep.exchange import to_brep_text

    out = Part.Shape()
    out.importBrepFromString(to_brep_text(shape))
    return out


def from_part(shape: "Part.Shape"):
    """A FreeCAD Part.Shape as a cadquery shape (a Solid when it holds one solid)."""
    from ..brep.exchange import from_brep_text

    cq_shape = from_brep_text(shape.exportBrepToString())
    solids = cq_shape.Solids()
    return solids[0] if len(solids) == 1 else cq_shape
