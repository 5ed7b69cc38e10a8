# SPDX-License-Identifier: LGPL-2.1-or-later
"""Rounds and chamfers on a knob (a cylinder swept onto a plate) and a plate, for the
tests of the operator, its plans, scripts and conversions."""

import math

import numpy as np

from Sketch2CADWorkbench.brep.operators import build
from Sketch2CADWorkbench.brep.protocol import Bevel, Box, EdgeSet, FaceRef, Mode, Protocol, Sweep

R, H, TOP = 15.0, 20.0, 25.0  # the knob: a cylinder of radius R, height H, top at z = TOP
K = 4 / 3 * (math.sqrt(2) - 1)  # a quarter circle's Bezier handle, per unit radius
BASE = Box((60.0, 60.0, 10.0))
KNOB = Sweep(
    FaceRef((0.0, 0.0, 5.0), (0.0, 0.0, 1.0)),
    (0.0, 0.0, 5.0),
    R,
    R,
    H,
    ((R, H / 3), (R, 2 * H / 3)),
    Mode.ADD,
)
DISK = FaceRef((0.0, 0.0, TOP), (0.0, 0.0, 1.0))


def quarter(c, into_f, into_other, r):
    """A quarter circle's Bezier from c + r into_f to c + r into_other, tangent to both."""
    c, a, b = (np.asarray(v, float) for v in (c, into_f, into_other))
    pts = [c + r * a, c + r * a * (1 - K), c + r * b * (1 - K), c + r * b]
    return tuple(tuple(map(float, p)) for p in pts)


def rim(r=3.0, **fields):
    """A bevel across the knob's top rim at (R, 0, TOP), drawn as a quarter circle."""
    c = (R, 0.0, TOP)
    return Bevel(DISK, c, None, quarter(c, (-1, 0, 0), (0, 0, -1), r), **fields)


def knob_with(op):
    return build(Protocol(BASE, (KNOB, op)))


def knob_volume():
    return build(Protocol(BASE, (KNOB,))).Volume()


def revolved(area, centroid_radius):
    """Pappus: the volume of a plane region revolved about an axis."""
    return 2 * math.pi * centroid_radius * area


def top_edge(**fields):
    """A bevel across the box's top front edge at its middle (y = -30, z = 5)."""
    c = (0.0, -30.0, 5.0)
    face = FaceRef((0.0, 0.0, 5.0), (0.0, 0.0, 1.0))
    return Bevel(face, c, None, quarter(c, (0, 1, 0), (0, 0, -1), 2.0), **fields)


def rounded_box():
    """The box with its four vertical edges filleted (r = 5) by the paper's crease form,
    so that the top outline is one tangent chain of four lines and four arcs."""
    ops = []
    for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1)):
        c = (30.0 * sx, 30.0 * sy, 5.0)
        ctrl = quarter(c, (-sx, 0, 0), (0, -sy, 0), 5.0)
        ops.append(
            Bevel(FaceRef((0.0, 0.0, 5.0), (0, 0, 1.0)), c, (c[0], c[1], -5.0), ctrl, radius=5.0)
        )
    return Protocol(BASE, tuple(ops))


def round_protocols() -> dict[str, Protocol]:
    """One protocol for each kind of round: a fillet, a chamfer and a freeform profile
    around a rim, a freeform profile along a straight edge, a face's outline, fillets
    along creases (the paper's form) and a freeform profile on a concave rim."""
    foot = (R, 0.0, 5.0)  # where the knob stands on the plate
    concave = Bevel(
        FaceRef((25.0, 25.0, 5.0), (0.0, 0.0, 1.0)),
        foot,
        None,
        quarter(foot, (1, 0, 0), (0, 0, 1), 3.0),
    )
    return {
        "rim fillet": Protocol(BASE, (KNOB, rim(3.0, radius=3.0))),
        "rim chamfer": Protocol(BASE, (KNOB, rim(3.0, distances=(2.0, 3.0)))),
        "rim freeform": Protocol(BASE, (KNOB, rim(3.0))),
        "edge freeform": Protocol(BASE, (top_edge(),)),
        "outline": Protocol(BASE, (top_edge(radius=2.0, edges=EdgeSet.OUTLINE),)),
        "creases": rounded_box(),
        "concave rim": Protocol(BASE, (KNOB, concave)),
    }
