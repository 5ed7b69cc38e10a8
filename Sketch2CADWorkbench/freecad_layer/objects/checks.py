# SPDX-License-Identifier: LGPL-2.1-or-later
"""Property values a user can type that no step can be built from, refused before the core
and OCCT see them, with the property's name in the message.

The core checks an operation's sizes against the model (brep/operators.py); what it
cannot see are a feature's raw properties: a NaN or infinite number (OCCT answers "wires
not planar" or an empty message), and the base box's sides, which the protocol loader
bounds (brep/fields.py) but the Box feature handed to OCCT unchecked.
"""

import math

import FreeCAD

from ...brep.fields import MAX_BOX_MM, MIN_BOX_MM


def _numbers(value, where: str = ""):
    """(where, number) for every number in a property's value: floats, Quantities,
    vectors and lists of them; other values (links, shapes, text) hold none."""
    if isinstance(value, bool):
        return
    if isinstance(value, (int, float)):
        yield where, float(value)
    elif isinstance(value, FreeCAD.Units.Quantity):
        yield where, value.Value
    elif isinstance(value, FreeCAD.Vector):
        for axis in "xyz":
            yield f"{where}.{axis}", getattr(value, axis)
    elif isinstance(value, (list, tuple)):
        for i, item in enumerate(value):
            yield from _numbers(item, f"{where}[{i}]")


def refuse_non_finite(obj) -> None:
    """Raise ValueError naming the first property of `obj` that holds NaN or infinity.

    Infinity typed into a length arrives as the largest double (FreeCAD clamps it), which
    the ranges of the core and of `box_side` refuse.
    """
    for prop in obj.PropertiesList:
        if prop in ("Shape", "Proxy"):
            continue
        for where, x in _numbers(getattr(obj, prop)):
            if not math.isfinite(x):
                raise ValueError(f"{obj.Label}: {prop}{where} is {x}; type a finite number")


def box_side(obj, prop: str) -> float:
    """A side of the base box (mm), refused outside what OCCT builds (as the loader does)."""
    value = getattr(obj, prop)
    side = float(getattr(value, "Value", value))
    if not MIN_BOX_MM <= side <= MAX_BOX_MM:
        raise ValueError(
            f"{obj.Label}: {prop} = {side:g} mm; a side of the box must be from "
            f"{MIN_BOX_MM:g} to {MAX_BOX_MM:g} mm"
        )
    return side
