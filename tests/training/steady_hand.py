# SPDX-License-Identifier: LGPL-2.1-or-later
"""A sample for the bounds' tests: one operation on a box's top, its strokes drawn exactly
(a steady hand) as another operation's curves, so the hand's error is known."""

from types import SimpleNamespace

from Sketch2CADWorkbench.brep.operators import make_box
from Sketch2CADWorkbench.brep.protocol import Box, FaceRef, Operation, Protocol
from Sketch2CADWorkbench.render.frustum import fit_camera
from Sketch2CADWorkbench.sketch.curves import operation_curves

TOP = FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0))  # the top of the 40 x 30 x 20 box


def drawn_sample(meant: Operation, drawn: Operation, direction, noise_level: int = 1):
    """A sample whose operation is `meant` on a 40 x 30 x 20 box and whose strokes are
    `drawn`'s curves, seen from `direction`, the hand's noise level `noise_level`."""
    base = Box((40.0, 30.0, 20.0))
    box = make_box(base)
    camera = fit_camera(box, direction)
    curves = operation_curves(box, drawn, camera.direction)
    return SimpleNamespace(
        context=Protocol(base),
        operation=meant,
        camera=camera,
        noise_level=noise_level,
        strokes=[camera.project(c.points)[0] for c in curves],
        stroke_parts=[int(c.label) for c in curves],
    )
