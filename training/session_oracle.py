# SPDX-License-Identifier: LGPL-2.1-or-later
"""How much of a sketch session its strokes tell: each step read by an oracle.

A session (examples/sessions/) comes with the protocol it means. For each step the oracle
knows the truth's structure: the operator, the base face, the Boolean, how many corners,
and which stroke draws which of its curves (`sketch.curves.operation_curves`, paired with
the strokes at the truth). It reads only the numbers from the strokes, by least squares
on what the generator's hand leaves of them (`datagen.strokes.perturb`): an open stroke's
two ends miss its curve's ends by independent Gaussians and the rest of it follows them,
so its ends are all it tells; a loop (a circle's stroke) starts anywhere and is lopsided,
so it counts by closeness, its samples' distances to the curve, weighed as one open
stroke's two ends. Started from the truth, the fit is the likeliest reading under that
hand when the strokes pin every number down, which a reading that has to find the
structure first cannot beat on average.

Each step is read on the true model before it; the readings together make the oracle's
protocol, replayed as an edited protocol is (a step's face followed where an earlier
one moved it). Its volume IoU with the truth says how close this session's strokes let
a reading end; the same with every reading snapped as the step's choices ask
(`interpret.snap_or_keep`, interpret's own snapping) says what the regularizer's priors
add to them. Each step's reading is also put alone into the true protocol: where the
session then ends says how far that step's strokes let a reading of the session go, and
the weakest step bounds it (`SessionOracle.weakest`); generously, since the numbers a
step's strokes do not tell (a sweep's inner profile points) stay the truth's.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import cadquery as cq
import numpy as np
from scipy.optimize import least_squares, linear_sum_assignment

from Sketch2CADWorkbench.brep.compare import volume_iou
from Sketch2CADWorkbench.brep.faces import FaceFrame, OperationError, is_curved, resolve_face
from Sketch2CADWorkbench.brep.operators import (
    apply_operation,
    apply_what_builds,
    make_box,
    replay,
)
from Sketch2CADWorkbench.brep.protocol import (
    AddSubPrism,
    Bevel,
    Extrude,
    Operation,
    Protocol,
    Shell,
    Sweep,
)
from Sketch2CADWorkbench.inference.fitting.common import (
    LOOP_WEIGHT,
    is_loop,
    loop_distances,
    loop_samples,
    match_ends,
    open_ends,
)
from Sketch2CADWorkbench.inference.fitting.regularize import chamfer_profile, fillet_profile
from Sketch2CADWorkbench.inference.fitting.verify import SketchFit, sketch_fit
from Sketch2CADWorkbench.inference.interpret import snap_or_keep
from Sketch2CADWorkbench.inference.session import Session, SketchStep
from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.render.frustum import context_camera
from Sketch2CADWorkbench.sketch.curves import operation_curves

FAILED_PX = 1e3  # the residual of numbers that build no curves


@dataclass(frozen=True)
class OracleStep:
    """One step read by the oracle.

    Attributes:
        reading: the oracle's operation, on the true model before the step.
        iou: its volume IoU with the truth's result, on that model.
        snapped, snapped_iou: the reading as the step's choices regularize it (the
            reading itself when they do not), and its volume IoU so.
        rms_px, truth_rms_px: the rms residual (view pixels) of the reading and of the
            truth: the hand's miss as the strokes show it.
        strokes: the strokes paired with a curve (the rest draw none).
        session_iou, snapped_session_iou: the final volume IoU of the protocol with
            this step as read (as snapped) and every other step exact: how far this
            step's strokes alone let the session end, wherever the others' end (None
            for a step read alone, outside `session_oracle`).
    """

    reading: Operation
    iou: float
    snapped: Operation
    snapped_iou: float
    rms_px: float
    truth_rms_px: float
    strokes: int
    session_iou: float | None = None
    snapped_session_iou: float | None = None


@dataclass(frozen=True)
class SessionOracle:
    """A session read by the oracle: its steps, and the final volume IoU with the truth of
    the oracle's protocol as read and as snapped by each step's choices."""

    steps: tuple[OracleStep, ...]
    final_iou: float
    regularized_iou: float

    @property
    def weakest(self) -> tuple[int, float]:
        """The step (from 1) whose better reading (as read or snapped) alone, every other
        step exact, ends the session lowest, and that final volume IoU: a reading that
        ends the session above it has to read that step better than the likeliest
        numbers of its strokes, and than the regularizer's priors make of them."""
        best = [max(s.session_iou, s.snapped_session_iou) for s in self.steps]
        k = int(np.argmin(best))
        return k + 1, best[k]


def _tuples(points) -> tuple:
    return tuple(tuple(map(float, p)) for p in points)


def _numbers(
    solid: cq.Shape, op: Operation
) -> tuple[np.ndarray, Callable[[np.ndarray], Operation]]:
    """The numbers the strokes tell of `op` (mm, in f's frame) and the operation they
    make. The structure stays the truth's: f, the Boolean, the polygon's corner count,
    a bevel's crease (its profile's ends slide along f's edges from c)."""
    rf = resolve_face(solid, op.face)
    frame = FaceFrame.tangent(rf.face, op.face) if is_curved(rf.face) else FaceFrame.of(rf.face)
    if isinstance(op, Extrude):
        return np.array([op.d]), lambda x: replace(op, d=float(x[0]))
    if isinstance(op, Shell):
        return np.array([op.t]), lambda x: replace(op, t=float(x[0]))
    if isinstance(op, AddSubPrism):
        poly = frame.to_2d(np.array(op.polygon, float))

        def prism(x):
            return replace(
                op, polygon=tuple(map(tuple, frame.to_3d(x[:-1].reshape(-1, 2)))), d=float(x[-1])
            )

        return np.r_[poly.ravel(), op.d], prism
    if isinstance(op, Sweep):
        centre = frame.to_2d(np.array(op.center, float))[0]

        def sweep(x):
            return replace(
                op,
                center=tuple(frame.to_3d(x[:2])[0]),
                r0=float(x[2]),
                r1=float(x[3]),
                d=float(x[4]),
                profile=tuple(map(tuple, x[5:].reshape(2, 2))),
            )

        return np.r_[centre, op.r0, op.r1, op.d, np.ravel(op.profile)], sweep
    if isinstance(op, Bevel):
        c, prof = np.array(op.corner, float), np.array(op.profile, float)
        ends = [prof[i] - c for i in (0, 3)]
        units = [e / np.linalg.norm(e) for e in ends]
        if op.radius is not None:  # a fillet: its radius, the profile its arc
            return np.array([op.radius]), lambda x: replace(
                op,
                radius=float(x[0]),
                profile=_tuples(fillet_profile(c, units[0], units[1], float(x[0]))),
            )
        if op.distances is not None:  # a chamfer: its two widths
            return np.array(op.distances), lambda x: replace(
                op,
                distances=(float(x[0]), float(x[1])),
                profile=_tuples(chamfer_profile(c, units[0], units[1], float(x[0]), float(x[1]))),
            )
        # l's own plane: f's for a crease, the plane normal to the edge for l across one
        v = units[1] - (units[1] @ units[0]) * units[0]
        plane = FaceFrame(c, np.cross(units[0], v), units[0], v / np.linalg.norm(v))

        def bevel(x):
            inner = plane.to_3d(x[2:].reshape(2, 2))
            return replace(op, profile=_tuples([c + x[0] * units[0], *inner, c + x[1] * units[1]]))

        return np.r_[[np.linalg.norm(e) for e in ends], plane.to_2d(prof[1:3]).ravel()], bevel
    raise TypeError(f"no oracle for {type(op).__name__}")


class _Pairing:
    """Which stroke draws which curve of the truth, and which way round."""

    def __init__(self, curves, strokes: list[np.ndarray], camera: OrthoCamera):
        ends = open_ends(strokes)
        opened = [i for i, s in enumerate(strokes) if not is_loop(s)]
        loops = [i for i, s in enumerate(strokes) if is_loop(s)]
        # an extruded disk's rim is a polyline back to its start, not a `closed` curve
        loop = [c.closed or np.allclose(c.points[0], c.points[-1]) for c in curves]
        self.open_curves = [k for k in range(len(curves)) if not loop[k]]
        closed = [k for k in range(len(curves)) if loop[k]]
        rows, cols, self.swapped = match_ends(
            self._curve_ends(curves, camera), ends.reshape(-1, 2, 2)
        )
        self.open = [(opened[r], self.open_curves[c]) for r, c in zip(rows, cols, strict=True)]
        self.loop_points = [loop_samples(strokes[i]) for i in loops]
        cost = np.zeros((len(loops), len(closed)))
        for r, p in enumerate(self.loop_points):
            for c, k in enumerate(closed):
                cost[r, c] = loop_distances(p, camera.project(curves[k].points)[0]).mean()
        rows, cols = linear_sum_assignment(cost) if cost.size else ((), ())
        self.loops = [(int(r), closed[c]) for r, c in zip(rows, cols, strict=True)]
        self.stroke_ends = np.array(
            [[strokes[i][0], strokes[i][-1]] for i, _ in self.open], float
        ).reshape(-1, 2, 2)
        self.stroke_ends = np.where(
            np.asarray(self.swapped, bool)[:, None, None],
            self.stroke_ends[:, ::-1],
            self.stroke_ends,
        )
        self.count = len(self.open) + len(self.loops)

    def _curve_ends(self, curves, camera: OrthoCamera) -> np.ndarray:
        return np.array(
            [camera.project(curves[k].points[[0, -1]])[0] for k in self.open_curves], float
        ).reshape(-1, 2, 2)

    def residuals(self, curves, camera: OrthoCamera) -> np.ndarray:
        """Open strokes' end gaps and loops' weighed distances (view pixels)."""
        ends = np.array(
            [camera.project(curves[k].points[[0, -1]])[0] for _, k in self.open], float
        ).reshape(-1, 2, 2)
        out = [(ends - self.stroke_ends).ravel()]
        weight = np.sqrt(LOOP_WEIGHT)
        for r, k in self.loops:
            out.append(
                weight * loop_distances(self.loop_points[r], camera.project(curves[k].points)[0])
            )
        return np.concatenate(out)


def oracle_reading(solid: cq.Shape, truth: Operation, step: SketchStep) -> OracleStep:
    """The oracle's reading of one step (module docstring), and that reading regularized
    as the step's choices ask.

    Args:
        solid: the true model before the step.
        truth: the operation the step's strokes mean.
        step: the strokes, in pixels of the view (camera) they were drawn in, and the
            step's choices.
    Raises:
        ValueError: no stroke pairs with a curve of the truth.
    """
    camera = step.camera
    direction = np.asarray(camera.direction, float)
    pairing = _Pairing(operation_curves(solid, truth, direction), step.strokes, camera)
    if not pairing.count:
        raise ValueError("no stroke of the step draws a curve of its operation")
    x0, build = _numbers(solid, truth)
    truth_res = pairing.residuals(operation_curves(solid, truth, direction), camera)

    def residuals(x):
        try:
            return pairing.residuals(operation_curves(solid, build(x), direction), camera)
        except (OperationError, ValueError):  # numbers that make no operation
            return np.full(len(truth_res), FAILED_PX)

    fit = least_squares(residuals, x0, x_scale=np.maximum(np.abs(x0), 1.0))
    reading = build(fit.x)
    c = step.choices
    snapped = reading
    if c.regularize:  # as interpret snaps, in pixels of the context camera it frames
        context = context_camera(camera, np.concatenate(step.strokes))
        strokes = [context.project(camera.unproject(np.asarray(s, float)))[0] for s in step.strokes]

        def fit_of(op: Operation) -> SketchFit:
            return sketch_fit(solid, op, context, strokes)

        snapped = snap_or_keep(
            solid, reading, resolve_face(solid, reading.face).face, fit_of, context, camera, c
        )[0]
    truth_solid = apply_operation(solid, truth)
    return OracleStep(
        reading,
        _iou(solid, reading, truth_solid),
        snapped,
        _iou(solid, snapped, truth_solid),
        _rms(fit.fun),
        _rms(truth_res),
        pairing.count,
    )


def _rms(r: np.ndarray) -> float:
    return float(np.sqrt(np.mean(r**2)))


def _iou(solid: cq.Shape, op: Operation, truth_solid: cq.Shape) -> float:
    """The volume IoU of `op` applied to `solid` with the truth's result; 0 when it does
    not build."""
    try:
        return volume_iou(apply_operation(solid, op), truth_solid)
    except OperationError:
        return 0.0


def session_oracle(
    session: Session, protocol: Protocol, on_step: Callable[[int], None] | None = None
) -> SessionOracle:
    """Every step of `session` read by the oracle against `protocol` (one operation per
    step), and the final volume IoUs of its protocol, as read and regularized.

    Args:
        on_step: called with each step's number once it is read (progress).
    Raises:
        ValueError: the session and the protocol differ in their number of steps.
    """
    if len(session.steps) != len(protocol.operations):
        raise ValueError(
            f"the session has {len(session.steps)} steps and the protocol "
            f"{len(protocol.operations)} operations: one per step is needed"
        )
    truths = replay(protocol)
    steps = []
    for k, (step, truth) in enumerate(zip(session.steps, protocol.operations, strict=True)):
        steps.append(oracle_reading(truths[k], truth, step))
        if on_step:
            on_step(k + 1)
    final, exact = truths[-1], list(protocol.operations)

    def alone(k: int, op: Operation) -> float:
        return volume_iou(apply_what_builds(truths[k], [op, *exact[k + 1 :]]), final)

    steps = [
        replace(s, session_iou=alone(k, s.reading), snapped_session_iou=alone(k, s.snapped))
        for k, s in enumerate(steps)
    ]
    return SessionOracle(
        tuple(steps),
        volume_iou(_built(protocol, [s.reading for s in steps]), final),
        volume_iou(_built(protocol, [s.snapped for s in steps]), final),
    )


def _built(protocol: Protocol, operations: list[Operation]) -> cq.Shape:
    """The protocol's box with the operations applied in turn (`apply_what_builds`)."""
    return apply_what_builds(make_box(protocol.base), operations)
