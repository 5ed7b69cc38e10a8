# SPDX-License-Identifier: LGPL-2.1-or-later
"""Sketch sessions drawn from a protocol's own curves, for the session oracle's tests."""

import numpy as np

from datagen.strokes import perturb
from Sketch2CADWorkbench.brep.operators import replay
from Sketch2CADWorkbench.brep.protocol import AddSubPrism, Box, FaceRef, Protocol, Sweep
from Sketch2CADWorkbench.inference.options import InterpretOptions
from Sketch2CADWorkbench.inference.session import SketchStep
from Sketch2CADWorkbench.render.frustum import fit_camera
from Sketch2CADWorkbench.sketch.curves import operation_curves

BASE = Box((40.0, 30.0, 20.0))
TOP = FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0))
POST = AddSubPrism(
    TOP, ((-10.0, -5.0, 10.0), (6.0, -5.0, 10.0), (6.0, 7.0, 10.0), (-10.0, 7.0, 10.0)), 12.0
)
BOSS = Sweep(
    FaceRef((-2.0, 1.0, 22.0), (0.0, 0.0, 1.0)),
    (-2.0, 1.0, 22.0),
    3.0,
    3.0,
    8.0,
    ((3.0, 8.0 / 3), (3.0, 16.0 / 3)),
)
NOT_REGULARIZED = InterpretOptions(regularize=False)


def sketched_step(
    protocol: Protocol,
    k: int,
    drawn_as=None,
    sigma: float = 0.0,
    seed: int = 0,
    choices: InterpretOptions = NOT_REGULARIZED,
) -> SketchStep:
    """Step k of the protocol sketched in a whole-model view: the curves of `drawn_as`
    (default: the step's own operation), each end missed by `sigma` px per axis."""
    solids = replay(protocol)
    op = drawn_as or protocol.operations[k]
    camera = fit_camera(solids[-1], (1.0, 0.7, -0.8), size=(800, 600))
    rng = np.random.default_rng(seed)
    strokes = []
    for c in operation_curves(solids[k], op, camera.direction):
        exact = camera.project(c.points)[0]
        strokes.append(
            perturb(exact[:-1] if c.closed else exact, rng, sigma, c.closed) if sigma else exact
        )
    return SketchStep(camera, strokes, choices)
