# SPDX-License-Identifier: LGPL-2.1-or-later
"""A box, a view of it and a stand-in for the networks that knows the answer, for the
interpret pipeline's tests.
"""

import numpy as np

from Sketch2CADWorkbench.brep.faces import resolve_face
from Sketch2CADWorkbench.brep.operators import make_box
from Sketch2CADWorkbench.brep.protocol import (
    AddSubPrism,
    Bevel,
    Box,
    Extrude,
    FaceRef,
    Mode,
    OperatorType,
    Sweep,
)
from Sketch2CADWorkbench.inference import adapters
from Sketch2CADWorkbench.inference.context import to_context
from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.render.strokes import rasterize
from Sketch2CADWorkbench.sketch.curves import operation_curves

TOP = FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0))


def view():
    d = np.array([0.6, 0.9, -1.2])
    return OrthoCamera((0.0, 0.0, 5.0), tuple(d / np.linalg.norm(d)), (0, 0, 1), 45.0, 800, 600)


class Oracle:
    """Answers like perfect networks for one known operation on one known solid."""

    def __init__(self, solid, op, strokes3d, labels, cam, renderer):
        self.solid, self.op, self.renderer = solid, op, renderer
        self.strokes3d, self.labels, self.view = strokes3d, labels, cam

    def classify(self, inputs):
        return np.eye(4)[list(OperatorType).index(self.op.type)]

    def context(self):
        """The sketch's context as the pipeline frames and renders it."""
        strokes = [self.view.project(p)[0] for p in self.strokes3d]
        return to_context(self.solid, strokes, self.view, self.renderer)

    def segment(self, inputs, op_type):
        ctx = self.context()
        face = resolve_face(self.solid, self.op.face).face
        index = next(i for i, f in enumerate(self.solid.Faces()) if f.isSame(face))
        curve = rasterize(
            ctx.strokes, ctx.camera.width, ctx.camera.height, [float(l) for l in self.labels]
        )
        return (ctx.maps.face_id == index).astype(np.float32), curve


def sketch(solid, op, cam):
    curves = operation_curves(solid, op, np.array(cam.direction))
    return [c.points for c in curves], [c.label for c in curves]


def front_bevel():
    """A box and a round of radius 6 at its front face's top right corner."""
    front = FaceRef((0.0, -15.0, 0.0), (0.0, -1.0, 0.0))
    k = 0.5523  # quarter-circle Bezier handle
    arc = (
        (14.0, -15.0, 10.0),
        (14.0 + 6 * k, -15.0, 10.0),
        (20.0, -15.0, 4.0 + 6 * k),
        (20.0, -15.0, 4.0),
    )
    return make_box(Box((40, 30, 20))), Bevel(front, (20.0, -15.0, 10.0), (20.0, 15.0, 10.0), arc)


def top_extrusion(renderer):
    """A box, a 9 mm extrusion of its top, and its sketch's context."""
    box = make_box(Box((40, 30, 20)))
    op = Extrude(TOP, 9.0)
    cam = view()
    pts, labels = sketch(box, op, cam)
    return box, op, Oracle(box, op, pts, labels, cam, renderer).context()


def top_extrusion_on_its_face(renderer):
    """`top_extrusion`'s box and context with F, the top's face index and C (the
    oracle's segmentation), as `_fit_extrude_on_face` takes them."""
    box = make_box(Box((40, 30, 20)))
    op = Extrude(TOP, 9.0)
    cam = view()
    pts, labels = sketch(box, op, cam)
    oracle = Oracle(box, op, pts, labels, cam, renderer)
    ctx = oracle.context()
    top, curve = oracle.segment(ctx.inputs, OperatorType.EXTRUDE)
    return box, ctx, top, int(np.bincount(ctx.maps.face_id[top > 0]).argmax()), curve


def drawn_on_top(renderer, op):
    """A box, the true stroke roles and context of `op`'s sketch on its top, the top's
    index and the perfect F and C maps there."""
    box = make_box(Box((40, 30, 20)))
    cam = view()
    pts, labels = sketch(box, op, cam)
    oracle = Oracle(box, op, pts, labels, cam, renderer)
    ctx = oracle.context()
    face_prob, curve = oracle.segment(ctx.inputs, op.type)
    index = int(np.bincount(ctx.maps.face_id[face_prob > 0.5]).argmax())
    return box, labels, ctx, index, face_prob, curve


def top_prism(renderer):
    """A box, a prism added on its top, its sketch's true roles and context, and the
    top's index and the perfect C map there."""
    op = AddSubPrism(TOP, ((6, -5, 10), (14, -5, 10), (14, 5, 10), (6, 5, 10)), 6.0, Mode.ADD)
    box, labels, ctx, index, _, curve = drawn_on_top(renderer, op)
    return box, op, labels, ctx, index, curve


def no_polygon_reading(monkeypatch):
    """The line search's path, as on a disk or where no stroke pairs with f's lines."""
    monkeypatch.setattr(adapters, "fit_extrude_by_ends", lambda *args: None)


TOP_SWEEP = Sweep(TOP, (4.0, -2.0, 10.0), 6.0, 4.0, 9.0, ((6.0, 3.0), (4.0, 6.0)), Mode.ADD)
