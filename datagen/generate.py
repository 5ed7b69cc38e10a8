# SPDX-License-Identifier: LGPL-2.1-or-later
"""Synthetic samples: a random sequence, a view of its last operation, strokes, labels
(paper, "Training data generation").

A sample's context is the protocol before its last operation; the sketch shows the last
operation's curves from an informative view; D, N and the face IDs are rendered from
the context solid in that same view (the context maps the network sees).

Data sets are made in blocks of PER_CONTEXT samples that share one context sequence,
because building a context costs about as much as the rest of a sample. The paper
makes one shape per protocol (10k protocols per sequence length 1 to 4); here each
sample of a block still draws its own last operation (1:1:4:2), view and strokes from
its own generator, and the blocks' context lengths take turns through 0 to 3
operations, so the distribution of sequence lengths and last operations is the
paper's, with a quarter as many distinct contexts.
"""

from __future__ import annotations

import cadquery as cq
import numpy as np
from OCP.gp import gp_Dir, gp_Lin, gp_Pnt
from OCP.IntCurvesFace import IntCurvesFace_ShapeIntersector

from Sketch2CADWorkbench.brep.faces import ResolvedFace, base_face_index, model_scale
from Sketch2CADWorkbench.brep.protocol import OperatorType, Shell
from Sketch2CADWorkbench.render.maps import MapRenderer
from Sketch2CADWorkbench.render.mesh import FaceMesh, tessellate
from Sketch2CADWorkbench.sketch.curves import Curve, operation_curves, rim_wires
from Sketch2CADWorkbench.sketch.labels import SHELL_WALL
from Sketch2CADWorkbench.sketch.visible import visible_curves

from .hand import P_HIDDEN_OUT, habits_of, people_strokes
from .rounds import round_tangent
from .sample import Sample
from .sequences import (
    LAST_OP_WEIGHTS,
    Drawn,
    Sequence,
    draw_type,
    sample_operation,
    sample_sequence,
)
from .strokes import sketch_strokes, stroke_maps
from .views import (
    OCCLUDED_BY,
    SCALE_RANGE,
    frame_curves,
    is_informative,
    shows_base_face,
    up_vector,
    view_direction,
)

IMAGE_SIZE = 256
PER_CONTEXT = 4
MAX_LENGTH = 4  # operations in a sequence, the last one included
VIEW_TRIES = 8  # views of one operation before drawing another operation
OP_TRIES = 10  # operations on one context before drawing another context
# With shells on (`--shells`), the last operation is drawn as LAST_OP_WEIGHTS with a shell
# as often as a sweep: complex operators more often, as the paper balances them
# (docs/measurements.md, generate.SHELL_WEIGHT).
SHELL_WEIGHT = 2
# A shell's sketch draws a line down an inner wall from a corner of the rim this often,
# over WALL_SPAN of the wall's depth: a designer's hint, which the reading must ignore
# (docs/measurements.md, generate.WALL_SHARE).
WALL_SHARE = 0.3
WALL_SPAN = (0.3, 1.0)
# Chordal tolerance of a context's mesh, relative to the model's diagonal: about half a
# pixel for a sketch a tenth of the model's size, so one mesh serves every view.
MESH_REL_TOLERANCE = 5e-4


class Context:
    """A context sequence ready to take last operations: its protocol, final solid and
    (made on first use) that solid's mesh."""

    def __init__(self, sequence: Sequence):
        self.protocol = sequence.protocol
        self.stage = sequence.stages[-1]
        self._mesh: FaceMesh | None = None

    @property
    def mesh(self) -> FaceMesh:
        if self._mesh is None:
            solid = self.stage.solid
            self._mesh = tessellate(solid, MESH_REL_TOLERANCE * model_scale(solid))
        return self._mesh


def last_op_weights(shells: bool) -> dict[OperatorType, int]:
    """The relative frequencies of the last operation's type: LAST_OP_WEIGHTS, and shells
    SHELL_WEIGHT where asked for."""
    return {**LAST_OP_WEIGHTS, OperatorType.SHELL: SHELL_WEIGHT} if shells else LAST_OP_WEIGHTS


def wall_curve(
    rng: np.random.Generator, result: cq.Shape, rf: ResolvedFace, op: Shell
) -> Curve | None:
    """A line down an inner wall of the shelled `result` from a random corner of the rim,
    WALL_SPAN of the way to the cavity's floor (None when the ray finds no floor)."""
    wires = rim_wires(rf.face, op.t)
    edges = [e for w in wires for e in w.Edges()]
    top = np.array(edges[int(rng.integers(len(edges)))].startPoint().toTuple())
    centre = np.mean([np.array(e.Center().toTuple()) for e in edges], axis=0)
    inward = centre - top
    inward -= (inward @ rf.normal) * rf.normal
    start = top + 1e-2 * op.t * inward / max(float(np.linalg.norm(inward)), 1e-12)
    hits = IntCurvesFace_ShapeIntersector()
    hits.Load(result.wrapped, 1e-6)
    hits.Perform(gp_Lin(gp_Pnt(*start), gp_Dir(*(-rf.normal))), 1e-6, 1e9)
    depths = [hits.WParameter(i) for i in range(1, hits.NbPnt() + 1)]
    if not depths:
        return None
    depth = min(depths) * rng.uniform(*WALL_SPAN)
    return Curve(np.stack([top, top - rf.normal * depth]), SHELL_WALL)


def sample_rng(seed: int, index: int, stream: int = 0) -> np.random.Generator:
    """The generator of item `index` of a data set, whatever worker makes it and when.

    Stream 0 draws samples, stream 1 the shared context sequences of blocks.
    """
    return np.random.default_rng(np.random.SeedSequence([seed, stream, index]))


def generate_sample(
    rng: np.random.Generator,
    noise_level: int,
    renderer: MapRenderer | None = None,
    size: int = IMAGE_SIZE,
) -> Sample:
    """One sample on a context of its own (sequence length 1 to 4, uniformly).

    Args:
        rng: the generator; the sample is a function of its state.
        noise_level: stroke noise level, 1, 2 or 3 (datagen/strokes.py).
        renderer: the offscreen renderer to use (a new one when None; reuse one across
            calls, making a window is slow).
        size: image side in pixels.
    """
    renderer = renderer or MapRenderer()
    length = int(rng.integers(1, MAX_LENGTH + 1))
    return sample_on(Context(sample_sequence(rng, length - 1)), rng, noise_level, renderer, size)


def generate_block(
    seed: int,
    block: int,
    noise_level: int,
    renderer: MapRenderer,
    size: int = IMAGE_SIZE,
    hidden_lines: bool = True,
    regular_share: float = 0.0,
    hand: str = "generator",
    shells: bool = False,
    round_share: float = 0.0,
) -> list[Sample]:
    """Samples block * PER_CONTEXT to (block + 1) * PER_CONTEXT - 1 of data set `seed`.

    They share one context of block % MAX_LENGTH operations, drawn from the block's own
    generator; sample i draws everything else from sample_rng(seed, i). Without
    `hidden_lines` the strokes draw only what the view sees (`view_sample`). Each
    operation, of the context and last, is regular (datagen/regular.py) with
    probability `regular_share`, decided by the generator that draws it. `hand`: who
    draws the strokes (datagen/hand.py). `shells`: last operations may be shells
    (`last_op_weights`); without it the samples are those of a build without shells. A
    last bevel is a round across an edge (datagen/rounds.py) with probability
    `round_share`.
    """
    context = Context(
        sample_sequence(
            sample_rng(seed, block, stream=1), block % MAX_LENGTH, regular_share=regular_share
        )
    )
    return [
        sample_on(
            context,
            sample_rng(seed, i),
            noise_level,
            renderer,
            size,
            hidden_lines=hidden_lines,
            regular_share=regular_share,
            hand=hand,
            shells=shells,
            round_share=round_share,
        )
        for i in range(block * PER_CONTEXT, (block + 1) * PER_CONTEXT)
    ]


def sample_on(
    context: Context,
    rng: np.random.Generator,
    noise_level: int,
    renderer: MapRenderer,
    size: int = IMAGE_SIZE,
    kind: OperatorType | None = None,
    hidden_lines: bool = True,
    regular_share: float = 0.0,
    hand: str = "generator",
    shells: bool = False,
    round_share: float = 0.0,
) -> Sample:
    """A sample whose last operation, of type `kind` (drawn 1:1:4:2 when None, and shells
    as `last_op_weights` says with `shells`), is drawn on `context`; every operation
    drawn is regular with probability `regular_share`, a bevel a round across an edge
    with probability `round_share`.

    The type is drawn once; an operation with no informative view is replaced by another
    of the same type, and a context that admits none (or none with such a view after
    OP_TRIES operations) by a fresh one of the same length.
    """
    kind = kind or draw_type(rng, last_op_weights(shells))
    tries = 0
    while True:
        drawn = (
            sample_operation(rng, context.stage, kind, regular_share, round_share=round_share)
            if tries < OP_TRIES
            else None
        )
        if drawn is None:
            context = Context(
                sample_sequence(rng, len(context.protocol.operations), regular_share=regular_share)
            )
            tries = 0
            continue
        sample = view_sample(rng, context, drawn, noise_level, renderer, size, hidden_lines, hand)
        if sample is not None:
            return sample
        tries += 1


def view_sample(
    rng: np.random.Generator,
    context: Context,
    drawn: Drawn,
    noise_level: int,
    renderer: MapRenderer,
    size: int = IMAGE_SIZE,
    hidden_lines: bool = True,
    hand: str = "generator",
) -> Sample | None:
    """The sample of the operation drawn on `context` from a random informative view, or
    None when VIEW_TRIES views all hide too much of the relevant curve or of the base
    face (datagen/views.py says which curve, and against which solid).

    With `hidden_lines` False the strokes draw only what the view sees of the model
    after the operation (`sketch.visible.visible_curves`), as a designer who leaves the
    hidden lines out; the training data draws every line. With `hand` "people" the
    strokes are drawn as a person does (datagen/hand.py), who also leaves the hidden
    lines out of a sample with probability P_HIDDEN_OUT; "people-HABIT", with that
    habit alone."""
    solid, op, result = context.stage.solid, drawn.op, drawn.result
    rf = drawn.face.resolved()  # f, drawn on this solid
    face = base_face_index(solid, rf.face)
    result_mesh = None
    wall = None  # a shell's line down a wall: drawn from rng for shells only
    if isinstance(op, Shell) and rng.random() < WALL_SHARE:
        wall = wall_curve(rng, result.solid, rf, op)
    along = round_tangent(rf.face, op)  # a round's view faces its profile's plane
    for _ in range(VIEW_TRIES):
        direction = view_direction(rng, rf.normal, along)
        up = up_vector(rng, direction)
        curves = operation_curves(solid, op, direction, rf) + ([wall] if wall else [])
        camera = frame_curves(
            np.concatenate([c.points for c in curves]),
            direction,
            up,
            rng.uniform(*SCALE_RANGE),
            size,
        )
        # l drawn across an edge runs where the result's surface will be (a round cuts
        # into the context's): it is tested against the result, as an extrusion's
        if OCCLUDED_BY[op.type] == "result" or along is not None:
            if result_mesh is None:
                result_mesh = tessellate(
                    result.solid, MESH_REL_TOLERANCE * model_scale(result.solid)
                )
            if not is_informative(curves, camera, renderer.render(result_mesh, camera)):
                continue
            maps = renderer.render(context.mesh, camera)
        else:
            maps = renderer.render(context.mesh, camera)
            if not is_informative(curves, camera, maps):
                continue
        if not shows_base_face(maps, face):
            continue
        habits = habits_of(hand)
        if hand != "generator" and hidden_lines and rng.random() < P_HIDDEN_OUT:
            hidden_lines = "hidden" not in habits
        if not hidden_lines:
            if result_mesh is None:
                result_mesh = tessellate(
                    result.solid, MESH_REL_TOLERANCE * model_scale(result.solid)
                )
            curves = visible_curves(curves, camera, renderer.render(result_mesh, camera))
        if hand != "generator":
            strokes, labels, ink = people_strokes(curves, camera, rng, noise_level, habits)
        else:
            strokes, labels = sketch_strokes(curves, camera, rng, noise_level)
            ink = stroke_maps(strokes, labels, size, size)
        return Sample(
            op_type=op.type,
            sketch=ink.sketch,
            depth=maps.depth,
            normal=maps.normal,
            face_id=maps.face_id,
            face_label=(maps.face_id == face).astype(np.float32),
            curve_label=ink.curve_label,
            stroke_mask=ink.stroke_mask,
            context=context.protocol,
            operation=op,
            camera=camera,
            strokes=strokes,
            stroke_parts=labels,
            noise_level=noise_level,
        )
    return None
