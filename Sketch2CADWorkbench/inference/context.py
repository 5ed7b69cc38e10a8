# SPDX-License-Identifier: LGPL-2.1-or-later
"""A sketch step's context: the strokes checked, framed and rasterised, the model rendered.

    check_sketch(strokes)                              refuse what no operation reads from
    to_context(solid, strokes, view, renderer) -> Context

The context camera frames twice the sketch's bounding box (paper, Sec. 4); the context
solid is rendered there to D, N and face IDs, the networks' inputs. Context also holds
what every reading of the step shares: the strokes as they are scored against, and the
scores and faces already computed.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import cadquery as cq
import numpy as np

from ..brep.faces import ResolvedFace, resolve_face
from ..brep.protocol import FaceRef, Operation, OperatorType
from ..render.camera import OrthoCamera
from ..render.frustum import context_camera
from ..render.maps import ContextMaps, MapRenderer
from ..render.strokes import rasterize
from .fitting.verify import DrawnStrokes, SketchFit, sketch_fit

# What one sketch step may hold: a person draws tens of strokes for an operation.
MAX_STROKES, MAX_POINTS = 200, 20000
MIN_SPAN_PX = 3.0  # strokes spanning less are a dot, not edges


class InterpretError(ValueError):
    """The sketch could not be turned into an operation; the message is for the user."""


@dataclass
class Context:
    """The rendered context of a sketch: camera, strokes in its pixels, maps, net inputs."""

    camera: OrthoCamera
    strokes: list[np.ndarray]
    maps: ContextMaps
    inputs: np.ndarray
    # `sketch_fit` by (solid, operation): a face's fit scores its readings, and the one it
    # keeps is scored again among the faces' readings
    fits: dict[tuple[cq.Shape, Operation], SketchFit] = field(
        default_factory=dict, repr=False, compare=False
    )
    # base faces resolved by (solid, reference): every reading on one planar face names
    # it alike, and each is scored and built
    faces: dict[tuple[cq.Shape, FaceRef], ResolvedFace] = field(
        default_factory=dict, repr=False, compare=False
    )
    # a primitive's stroke roles by (solid, operator, face index), each a list of per-stroke
    # roles (`adapters._fit_by_roles`): read alike for either Boolean, and a reading's
    # other Boolean is fitted on its face again (`search.weigh_the_other_boolean`)
    roles: dict[tuple[cq.Shape, OperatorType, int], list[list[int]]] = field(
        default_factory=dict, repr=False, compare=False
    )
    # seconds spent building readings' results (`builds_a_change`): B-rep work done while
    # reading, timed as the B-rep stage
    build_s: float = field(default=0.0, compare=False)
    # renders what a reading's result lets the view see (`search.weigh_the_other_boolean`);
    # None: readings are weighed by every line only
    renderer: MapRenderer | None = field(default=None, repr=False, compare=False)

    @cached_property
    def drawn(self) -> DrawnStrokes:
        """The strokes as every reading of them is scored against them."""
        return DrawnStrokes(self.strokes, (self.camera.height, self.camera.width))

    def resolved(self, solid: cq.Shape, ref: FaceRef) -> ResolvedFace:
        """`resolve_face` of ref on `solid`, once for each (OperationError as it)."""
        if (solid, ref) not in self.faces:
            self.faces[solid, ref] = resolve_face(solid, ref)
        return self.faces[solid, ref]

    def sketch_fit(self, solid: cq.Shape, op: Operation) -> SketchFit:
        """`verify.sketch_fit` of op on `solid` and the strokes, once for each."""
        if (solid, op) not in self.fits:
            self.fits[solid, op] = sketch_fit(
                solid, op, self.camera, self.drawn, face=self.resolved(solid, op.face)
            )
        return self.fits[solid, op]


def to_context(
    solid: cq.Shape,
    strokes: list[np.ndarray],
    view: OrthoCamera,
    renderer: MapRenderer,
    size: int = 256,
) -> Context:
    """Frame, transform and rasterise the sketch and render the context maps."""
    if not strokes or all(len(s) < 2 for s in strokes):
        raise InterpretError("there are no strokes to interpret")
    pts = np.concatenate([np.asarray(s, float) for s in strokes])
    cam = context_camera(view, pts, size=size)
    ctx = [cam.project(view.unproject(np.asarray(s, float)))[0] for s in strokes if len(s) >= 2]
    maps = renderer.render(solid, cam)
    sketch = rasterize(ctx, cam.width, cam.height)
    inputs = np.concatenate([sketch[None], maps.depth[None], maps.normal]).astype(np.float32)
    return Context(cam, ctx, maps, inputs, renderer=renderer)


def check_sketch(strokes: list[np.ndarray]) -> None:
    """Refuse at once what no operation can be read from: too many strokes or points for a
    sketch a person draws (the fitting's cost grows with them), non-finite points, or
    strokes that span less than MIN_SPAN_PX (a dot).

    Raises:
        InterpretError: saying which.
    """
    if not strokes:
        raise InterpretError("no strokes: draw the operation's edges over the model")
    if len(strokes) > MAX_STROKES:
        raise InterpretError(
            f"{len(strokes)} strokes: one operation takes at most "
            f"{MAX_STROKES}; clear the strokes and draw it again"
        )
    points = sum(len(s) for s in strokes)
    if points > MAX_POINTS:
        raise InterpretError(f"{points} stroke points: at most {MAX_POINTS} per operation")
    every = np.concatenate([np.asarray(s, float).reshape(-1, 2) for s in strokes])
    if not np.isfinite(every).all():
        raise InterpretError("a stroke point is not a finite number")
    if float(np.ptp(every, axis=0).max()) < MIN_SPAN_PX:
        raise InterpretError(
            f"the strokes span less than {MIN_SPAN_PX} pixels: draw the "
            "operation's edges, not a dot"
        )
