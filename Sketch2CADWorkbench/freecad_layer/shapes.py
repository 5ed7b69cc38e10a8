# SPDX-License-Identifier: LGPL-2.1-or-later
"""Shapes crossing between cadquery's OCCT and FreeCAD's OCCT, as BREP text."""
import FreeCAD  # noqa: F401  (Part needs FreeCAD imported first)
import Part

from ..brep.exchange import from_brep_text, to_brep_text


def to_part(shape) -> "Part.Shape":
    """A cadquery shape as a FreeCAD Part.Shape."""
    out = Part.Shape()
    out.importBrepFromString(to_brep_text(shape))
    return out


def from_part(shape: "Part.Shape"):
    """A FreeCAD Part.Shape as a cadquery shape (a Solid when it holds one solid)."""
    cq_shape = from_brep_text(shape.exportBrepToString())
    solids = cq_shape.Solids()
    return solids[0] if len(solids) == 1 else cq_shape
