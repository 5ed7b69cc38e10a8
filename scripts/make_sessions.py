# SPDX-License-Identifier: LGPL-2.1-or-later
"""Make example sketch sessions from example protocols (how examples/sessions/ was made).

Each operation of a protocol is "sketched" the way the training data is: its sketch
curves, seen from an informative view (20-80 degrees off the base face's normal, the
relevant curve at least 80% visible), drawn as freehand strokes with level-1 noise.
The strokes are stored in a whole-model 800 x 600 view, as a designer's screen would
show them. The ground-truth protocol is kept beside the session for comparison. Each
step is read with regularization on and its designer's grid (`designer_grid`), as a
designer sketching it would have the workbench set.

    .bin/python scripts/make_sessions.py camera mixer hammer
    .bin/python scripts/make_sessions.py bolt lamp pipe   # (nut: no informative view for step 3)
    .bin/python scripts/make_sessions.py knob
"""

import re
import sys
from pathlib import Path

import numpy as np

from datagen.rounds import round_tangent
from datagen.strokes import sketch_strokes
from datagen.views import frame_curves, is_informative, up_vector, view_direction
from Sketch2CADWorkbench.brep.faces import resolve_face
from Sketch2CADWorkbench.brep.operators import replay
from Sketch2CADWorkbench.brep.protocol import Bevel, EdgeSet, Mode, load
from Sketch2CADWorkbench.inference.options import InterpretOptions
from Sketch2CADWorkbench.inference.session import Session, SketchStep
from Sketch2CADWorkbench.render.frustum import fit_camera
from Sketch2CADWorkbench.render.maps import MapRenderer
from Sketch2CADWorkbench.sketch.curves import operation_curves

ROOT = Path(__file__).resolve().parents[1]


def designer_grid(protocol_text: str) -> float:
    """The length grid (mm) a protocol was designed on: 0.5 where any of its values is a
    half millimetre, else 1 (values on neither, such as a profile's control points at
    thirds, say nothing of it)."""
    values = [float(v) for v in re.findall(r"-?\d+\.?\d*", protocol_text)]
    halves = [v for v in values if abs(2 * v - round(2 * v)) < 1e-9]
    return 0.5 if any(abs(v - round(v)) > 1e-9 for v in halves) else 1.0


def make(name: str, seed: int = 0) -> Session:
    path = ROOT / "examples" / "protocols" / f"{name}.json"
    protocol = load(path)
    grid = designer_grid(path.read_text())
    solids = replay(protocol)
    rng = np.random.default_rng(seed)
    renderer = MapRenderer()
    steps = []
    for i, op in enumerate(protocol.operations):
        solid = solids[i]
        rf = resolve_face(solid, op.face)
        along = round_tangent(rf.face, op)
        for _ in range(200):
            direction = view_direction(rng, rf.normal, along)
            up = up_vector(rng, direction)
            curves = operation_curves(solid, op, direction, rf)
            pts = np.concatenate([c.points for c in curves])
            ctx = frame_curves(pts, direction, up, 2.0)
            # l drawn across an edge runs where the result's surface will be, not on the
            # context's (datagen/views.py, OCCLUDED_BY)
            seen = solids[i + 1] if along is not None else solid
            if is_informative(curves, ctx, renderer.render(seen, ctx)):
                break
        else:
            raise RuntimeError(f"{name} step {i + 1}: no informative view")
        strokes, _ = sketch_strokes(curves, ctx, rng, 1)
        view = fit_camera(
            np.stack(
                [np.minimum(pts.min(0), _bb(solid)[0]), np.maximum(pts.max(0), _bb(solid)[1])]
            ),
            direction,
            up,
            1.2,
            (800, 600),
        )
        moved = [view.project(ctx.unproject(s))[0] for s in strokes]
        # Modes the strokes cannot show, said in the panel: replace and intersect, and
        # subtract, since a hole and the boss standing on its rim draw the same lines
        # (paper Fig. 5b): the designer drawing a hole picks subtract (or clicks the flip).
        option = (
            op.mode
            if getattr(op, "mode", None) in (Mode.REPLACE, Mode.INTERSECT, Mode.SUBTRACT)
            else None
        )
        # a bevel's edge set is the panel's choice, as the designer sets it
        edges = op.edges if isinstance(op, Bevel) else EdgeSet.DRAWN
        choices = InterpretOptions(option=option, regularize=True, snap_step=grid, edges=edges)
        steps.append(SketchStep(view, moved, choices))
    return Session(protocol.base, steps)


def _bb(solid):
    b = solid.BoundingBox()
    return np.array([b.xmin, b.ymin, b.zmin]), np.array([b.xmax, b.ymax, b.zmax])


if __name__ == "__main__":
    out = ROOT / "examples" / "sessions"
    out.mkdir(exist_ok=True)
    for k, name in enumerate(sys.argv[1:]):
        make(name, seed=k).save(out / f"{name}.json")
        print(f"{out / name}.json")
