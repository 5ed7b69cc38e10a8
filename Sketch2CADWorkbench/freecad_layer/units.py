# SPDX-License-Identifier: LGPL-2.1-or-later
"""Values as the user reads them: in the unit schema chosen in FreeCAD's preferences."""

import FreeCAD

AXES = {
    (1, 0, 0): "+X",
    (-1, 0, 0): "-X",
    (0, 1, 0): "+Y",
    (0, -1, 0): "-Y",
    (0, 0, 1): "+Z",
    (0, 0, -1): "-Z",
}


def length(mm: float) -> str:
    """A length in mm in the user's units ('9.54 mm', '0.38 in')."""
    return FreeCAD.Units.Quantity(float(mm), FreeCAD.Units.Length).UserString


def point(p) -> str:
    """A point in mm as '(x, y, z) unit' in the user's units ('(0.00, 0.00, 10.00) mm')."""
    largest = max(abs(float(c)) for c in p) or 1.0
    _, factor, unit = FreeCAD.Units.Quantity(largest, FreeCAD.Units.Length).getUserPreferred()
    decimals = FreeCAD.ParamGet("User parameter:BaseApp/Preferences/Units").GetInt("Decimals", 2)
    coords = (round(float(c) / factor, decimals) + 0.0 for c in p)  # no "-0.00"
    return "(" + ", ".join(f"{c:.{decimals}f}" for c in coords) + f") {unit}"


def direction(n) -> str:
    """A unit vector: '+Z' for an axis, else its components."""
    key = tuple(round(float(c), 6) + 0.0 for c in n)
    return AXES.get(key, "(" + ", ".join(f"{c:.3g}" for c in key) + ")")


# The default length grid: a whole unit of the schema's, in mm (inch schemas: 0.05 in, as
# decimal inches are read); halved where the view shows the snapping tolerance
# (regularize.SNAP_PX) within a quarter of it: a zoomed-in view, drawn that precisely.
METRIC_GRID, INCH_GRID = 1.0, 1.27
HALF_GRID_TOL = 0.25


def length_grid(pixel_mm: float) -> float:
    """The grid step (mm) a designer reads lengths on in the user's unit schema, for a view
    of `pixel_mm` mm per pixel: 1 mm in mm schemas, 0.5 mm where the strokes are that
    precise (HALF_GRID_TOL)."""
    from ..inference.fitting.regularize import SNAP_PX

    _, _, unit = FreeCAD.Units.Quantity(10.0, FreeCAD.Units.Length).getUserPreferred()
    step = INCH_GRID if unit.strip() in ("in", '"', "ft", "'", "thou", "mil") else METRIC_GRID
    if SNAP_PX * pixel_mm <= HALF_GRID_TOL * step:
        step /= 2
    return step
