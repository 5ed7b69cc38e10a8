# SPDX-License-Identifier: LGPL-2.1-or-later
"""Holes drawn as a designer draws them, and how many the pipeline reads as that hole.

A hole is a subtract prism on a planar face of a random model (a box, or a box after
one or two random operations, so that faces stand above others), drawn through the
data generator's own synthesis: an informative view of f's front, the curves the
generator draws for the prism, and level-1 freehand strokes (end points moved, a
wobble across each stroke). Drawn with every line, as the training sketches are, a hole
and a boss standing on its rim draw the same lines (paper, Fig. 5b); a designer who
leaves the hidden lines out draws the parts of lines the model after the hole lets the
view see (`hidden_lines=False`), and those differ. Used by tests/inference/test_holes.py and by
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
from Sketch2CADWorkbench.brep.compare import volume_iou
from Sketch2CADWorkbench.brep.faces import OperationError, resolve_face
from Sketch2CADWorkbench.brep.operators import apply_operation
from Sketch2CADWorkbench.brep.protocol import AddSubPrism, Mode, OperatorType
from Sketch2CADWorkbench.inference.context import InterpretError
from Sketch2CADWorkbench.inference.fitting.verify import sketch_fit
from Sketch2CADWorkbench.inference.interpret import interpret
from Sketch2CADWorkbench.inference.options import InterpretOptions
from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.render.maps import MapRenderer

READ_IOU = 0.95  # the evaluation's recovery criterion (training/recovery.py)


@dataclass
class DrawnHole:
    """A hole's context solid, its strokes in `camera`'s pixels, and the true result."""

    solid: cq.Solid
    strokes: list[np.ndarray]
    camera: OrthoCamera
    hole: AddSubPrism
    result: cq.Solid


def designer_holes(
    count: int, seed: int, renderer: MapRenderer, hidden_lines: bool
) -> Iterator[DrawnHole]:
    """`count` holes, each a function of (seed, its index), drawn with every line
    (`hidden_lines`) or only with what the view sees."""
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
        op = dataclasses.replace(op, mode=Mode.SUBTRACT)
        try:
            result = apply_operation(stage.solid, op)
        except OperationError:
            continue
        if stage.volume - result.Volume() < MIN_VOLUME_CHANGE * stage.volume:
            continue  # a hole that removes next to nothing is no hole to draw
        sample = view_sample(
            rng, context, Drawn(op, face, Stage(result)), 1, renderer, hidden_lines=hidden_lines
        )
        if sample is None:
            continue
        made += 1
        yield DrawnHole(stage.solid, sample.strokes, sample.camera, op, result)


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
        ("" when read as the hole, a subtraction whose result has a volume IoU of
        READ_IOU with the true one, else what it was read as instead; the other Boolean
        the reading names as fitting as well, or None).
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
    if got.op_type is not OperatorType.ADDSUB or op.mode is not Mode.SUBTRACT:
        mode = getattr(op, "mode", None)
        return f"read as {got.op_type.value}" + (
            f" ({mode.value})" if mode else ""
        ), got.other_option
    iou = volume_iou(got.solid, hole.result)
    return ("" if iou >= READ_IOU else f"a subtraction with volume IoU {iou:.2f}"), got.other_option
