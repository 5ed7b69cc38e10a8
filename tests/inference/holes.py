# SPDX-License-Identifier: LGPL-2.1-or-later
"""Holes drawn as a designer draws them, and how many the pipeline reads as that hole.

A hole is a subtract prism on a planar face of a random model (a box, or a box after
one or two random operations, so that faces stand above others), drawn through the
data generator's own synthesis: an informative view of f's front, the curves the
generator draws for the prism, and level-1 freehand strokes (end points moved, a
wobble across each stroke). Drawn with every line, as the training sketches are, a hole
and a boss standing on its rim draw the same lines (paper, Fig. 5b); a designer who
leaves the hidden lines out draws the parts of lines the model after the hole lets the
view see (`hidden_lines=False`), and those differ. The generator's prisms stand
anywhere on f, so many of these holes run over f's edge: notches, drawn as the
generator draws them, with the primitive's whole outline (`kind` picks holes wholly
on f, or notches). Used by tests/inference/test_holes.py and by
`scripts/hole_rate.py`, which prints the rates for more holes.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator
from dataclasses import dataclass

import cadquery as cq
import numpy as np

from datagen.generate import Context, sample_rng, view_sample
from datagen.operations import sample_prism
from datagen.sequences import MIN_VOLUME_CHANGE, Drawn, Stage, sample_sequence
from datagen.strokes import sketch_strokes
from datagen.views import frame_curves, up_vector
from Sketch2CADWorkbench.brep.compare import volume_iou
from Sketch2CADWorkbench.brep.faces import OperationError, model_scale, resolve_face
from Sketch2CADWorkbench.brep.geometry import resample_polyline
from Sketch2CADWorkbench.brep.operators import apply_operation, replay, sweep_tool
from Sketch2CADWorkbench.brep.protocol import (
    AddSubPrism,
    Box,
    FaceRef,
    Mode,
    Protocol,
    Sweep,
)
from Sketch2CADWorkbench.inference.context import InterpretError
from Sketch2CADWorkbench.inference.fitting.primitive import fraction_on_face
from Sketch2CADWorkbench.inference.fitting.verify import sketch_fit
from Sketch2CADWorkbench.inference.interpret import interpret
from Sketch2CADWorkbench.inference.options import InterpretOptions
from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.render.maps import MapRenderer
from Sketch2CADWorkbench.sketch.curves import Curve, operation_curves
from Sketch2CADWorkbench.sketch.labels import END, START
from Sketch2CADWorkbench.sketch.visible import visible_curves

READ_IOU = 0.95  # the evaluation's recovery criterion (training/recovery.py)
KINDS = ("any", "hole", "notch")  # of `designer_holes`: a hole wholly on f, or over its edge


@dataclass
class DrawnHole:
    """A hole's context solid, its strokes in `camera`'s pixels, and the true result."""

    solid: cq.Solid
    strokes: list[np.ndarray]
    camera: OrthoCamera
    hole: AddSubPrism | Sweep
    result: cq.Solid
    notch: bool = False  # the rim runs over f's edge
    # a line besides the rim is drawn: a rim alone (the view hiding every side edge
    # and the floor) does not say how deep the hole is
    depth_drawn: bool = True


def rim_on_face(solid: cq.Solid, op: AddSubPrism) -> float:
    """The share of the prism's outline on f's plane that lies on f (1 for a hole
    wholly on f, less for a notch)."""
    rim = np.array(op.polygon + op.polygon[:1], float)
    face = resolve_face(solid, op.face).face
    return fraction_on_face(
        face, resample_polyline(rim, 40 * len(op.polygon)), 1e-6 * model_scale(solid)
    )


def designer_holes(
    count: int,
    seed: int,
    renderer: MapRenderer,
    hidden_lines: bool,
    mode: Mode = Mode.SUBTRACT,
    kind: str = "any",
) -> Iterator[DrawnHole]:
    """`count` holes (bosses with `mode` ADD), each a function of (seed, its index), drawn
    with every line (`hidden_lines`) or only with what the view sees; `kind` (one of
    KINDS) keeps only holes wholly on f, or only notches."""
    made, index = 0, 0
    while made < count:
        rng = sample_rng(seed, index)
        index += 1
        context = Context(sample_sequence(rng, int(rng.integers(0, 3))))
        stage = context.stage
        if not stage.faces:
            continue
        face = stage.faces[int(rng.integers(len(stage.faces)))]
        op = sample_prism(rng, stage.solid, face)
        if op is None:
            continue
        op = dataclasses.replace(op, mode=mode)
        notch = rim_on_face(stage.solid, op) < 1.0
        if kind != "any" and notch != (kind == "notch"):
            continue
        try:
            result = apply_operation(stage.solid, op)
        except OperationError:
            continue
        if abs(stage.volume - result.Volume()) < MIN_VOLUME_CHANGE * stage.volume:
            continue  # a hole that removes next to nothing is no hole to draw
        sample = view_sample(
            rng, context, Drawn(op, face, Stage(result)), 1, renderer, hidden_lines=hidden_lines
        )
        if sample is None:
            continue
        made += 1
        depth_drawn = any(part != END for part in sample.stroke_parts)
        yield DrawnHole(stage.solid, sample.strokes, sample.camera, op, result, notch, depth_drawn)


# A box that had a boss on its top, and a drilled hole (r 6 mm, 15 deep) into each of
# the faces FreeCAD's isometric view shows: its front (-Y), right (+X) and top.
BOSSED_BOX = Protocol(
    Box((40.0, 30.0, 20.0)),
    (
        AddSubPrism(
            FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0)),
            ((-16.0, -2.0, 10.0), (0.0, -2.0, 10.0), (0.0, 10.0, 10.0), (-16.0, 10.0, 10.0)),
            12.0,
        ),
    ),
)
HOLE_CENTRES = {
    "-Y": ((0.0, -15.0, 0.0), (0.0, -1.0, 0.0)),
    "+X": ((20.0, 0.0, 0.0), (1.0, 0.0, 0.0)),
    "top": ((10.0, -6.0, 10.0), (0.0, 0.0, 1.0)),
}
ISOMETRIC = (-1.0, 1.0, -1.0)  # FreeCAD's isometric view direction, into the scene
# How a hole's lines are drawn: every line (as the training sketches are); only what the
# view sees of the model after the hole (the rim, and of the depth lines and the bottom
# circle what the opening shows); as a designer draws a drilled hole ("depth": the rim,
# the depth lines whole, and the bottom circle's half away from the viewer, which the
# opening would show were the hole shallow); or the lines the hole's own cylinder would
# show, seen as a solid (rim and depth lines, the bottom circle's half behind the
# cylinder left out)
LINE_STYLES = ("all", "seen", "depth", "own")


def drilled_hole(face: str, r: float = 6.0, d: float = 15.0) -> Sweep:
    """A cylindrical hole of radius r and depth d into `face` of BOSSED_BOX (a key of
    HOLE_CENTRES), as a subtract sweep whose profile is a straight line."""
    centre, normal = HOLE_CENTRES[face]
    return Sweep(
        FaceRef(centre, normal), centre, r, r, d, ((r, d / 3), (r, 2 * d / 3)), Mode.SUBTRACT
    )


def gui_holes(
    face: str,
    count: int,
    seed: int,
    renderer: MapRenderer,
    lines: str,
    noise_level: int = 1,
    turn_deg: float = 8.0,
) -> Iterator[DrawnHole]:
    """`count` drawings of `drilled_hole(face)` on BOSSED_BOX in FreeCAD's isometric view
    turned by about `turn_deg` degrees, with the data generator's freehand strokes of
    `noise_level`. `lines`: one of LINE_STYLES."""
    solid = replay(BOSSED_BOX)[-1]
    op = drilled_hole(face)
    result = apply_operation(solid, op)
    cylinder = sweep_tool(solid, resolve_face(solid, op.face), op, model_scale(solid))
    rng = np.random.default_rng(seed)
    for _ in range(count):
        direction = np.asarray(ISOMETRIC, float) / np.sqrt(3) + rng.normal(
            0.0, np.radians(turn_deg) / 2, 3
        )
        direction /= np.linalg.norm(direction)
        curves = operation_curves(solid, op, direction)
        camera = frame_curves(
            np.concatenate([c.points for c in curves]), direction, up_vector(rng, direction), 2.0
        )
        if lines == "depth":
            curves = [c if c.label != START else far_half(c, direction) for c in curves]
        elif lines != "all":
            shown = result if lines == "seen" else cylinder
            curves = visible_curves(curves, camera, renderer.render(shown, camera))
        strokes, _ = sketch_strokes(curves, camera, rng, noise_level)
        yield DrawnHole(solid, strokes, camera, op, result)


def far_half(circle: Curve, direction: np.ndarray) -> Curve:
    """The half of a closed circle (Curve) lying away from a viewer looking along
    `direction`, as one open curve."""
    pts = circle.points
    far = (pts - pts.mean(axis=0)) @ direction > 0
    start = int(np.argmax(far & ~np.roll(far, 1)))  # where the far run begins
    pts, far = np.roll(pts, -start, axis=0), np.roll(far, -start)
    return Curve(pts[: int(np.argmin(far)) or len(pts)], circle.label)


def rim_boss(hole: DrawnHole) -> AddSubPrism:
    """The boss that draws the hole's lines (paper, Fig. 5b): it stands on the hole's floor
    outline slid back along the view onto f, as tall as the hole is deep, so its top
    outline is the rim seen along the view."""
    rf = resolve_face(hole.solid, hole.hole.face)
    normal, view = np.asarray(rf.normal, float), np.asarray(hole.camera.direction, float)
    floor = np.array(hole.hole.polygon, float) - hole.hole.d * normal
    base = floor - view * (hole.hole.d / float(-view @ normal))
    return dataclasses.replace(hole.hole, polygon=tuple(map(tuple, base)), mode=Mode.ADD)


def seen_errors(hole: DrawnHole, renderer: MapRenderer) -> tuple[float, float] | None:
    """How far (px, `SketchFit.misfit_px` with only the lines each result lets the
    view see) the hole's own sketch and that of the boss on its rim lie from the
    strokes; None when that boss cannot stand there (then nothing is ambiguous)."""
    out = []
    for op in (hole.hole, rim_boss(hole)):
        try:
            result = apply_operation(hole.solid, op)
        except OperationError:
            return None
        seen = renderer.render(result, hole.camera)
        out.append(sketch_fit(hole.solid, op, hole.camera, hole.strokes, seen).misfit_px)
    return out[0], out[1]


def read_as_the_hole(
    hole: DrawnHole, predictor, renderer: MapRenderer, option: Mode | None = None
) -> tuple[str, Mode | None]:
    """How the pipeline reads the hole's strokes, with the designer's Boolean choice
    `option` (None: no choice).

    Returns:
        ("" when read as the hole, a primitive of its Boolean whose result has a volume
        IoU of READ_IOU with the true one, else what it was read as instead; the other
        Boolean the reading names as fitting as well, or None).
    """
    try:
        got = interpret(
            hole.solid,
            hole.strokes,
            hole.camera,
            predictor,
            renderer,
            InterpretOptions(regularize=False, option=option),
        )
    except InterpretError as e:
        return f"refused: {e}", None
    op = got.operations[0]
    mode = getattr(op, "mode", None)
    if mode is not hole.hole.mode:
        return f"read as {got.op_type.value}" + (
            f" ({mode.value})" if mode else ""
        ), got.other_option
    iou = volume_iou(got.solid, hole.result)
    return (
        "" if iou >= READ_IOU else f"a {got.op_type.value} ({mode.value}) with volume IoU {iou:.2f}"
    ), got.other_option
