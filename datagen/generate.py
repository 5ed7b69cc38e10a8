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

import numpy as np

from Sketch2CADWorkbench.brep.faces import base_face_index, model_scale
from Sketch2CADWorkbench.brep.protocol import OperatorType
from Sketch2CADWorkbench.render.maps import MapRenderer
from Sketch2CADWorkbench.render.mesh import FaceMesh, tessellate
from Sketch2CADWorkbench.sketch.curves import operation_curves
from Sketch2CADWorkbench.sketch.visible import visible_curves

from .hand import P_HIDDEN_OUT, people_strokes
from .rounds import round_tangent
from .sample import Sample
from .sequences import Drawn, Sequence, draw_type, sample_operation, sample_sequence
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
    round_share: float = 0.0,
) -> list[Sample]:
    """Samples block * PER_CONTEXT to (block + 1) * PER_CONTEXT - 1 of data set `seed`.

    They share one context of block % MAX_LENGTH operations, drawn from the block's own
    generator; sample i draws everything else from sample_rng(seed, i). Without
    `hidden_lines` the strokes draw only what the view sees (`view_sample`). Each
    operation, of the context and last, is regular (datagen/regular.py) with
    probability `regular_share`, decided by the generator that draws it. `hand`: who
    draws the strokes (datagen/hand.py). A last bevel is a round across an edge
    (datagen/rounds.py) with probability `round_share`.
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
    round_share: float = 0.0,
) -> Sample:
    """A sample whose last operation, of type `kind` (drawn 1:1:4:2 when None), is drawn
    on `context`; every operation drawn is regular with probability `regular_share`, a
    bevel a round across an edge with probability `round_share`.

    The type is drawn once; an operation with no informative view is replaced by another
    of the same type, and a context that admits none (or none with such a view after
    OP_TRIES operations) by a fresh one of the same length.
    """
    kind = kind or draw_type(rng)
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
    lines out of a sample with probability P_HIDDEN_OUT."""
    solid, op, result = context.stage.solid, drawn.op, drawn.result
    rf = drawn.face.resolved()  # f, drawn on this solid
    face = base_face_index(solid, rf.face)
    result_mesh = None
    along = round_tangent(rf.face, op)  # a round's view faces its profile's plane
    for _ in range(VIEW_TRIES):
        direction = view_direction(rng, rf.normal, along)
        up = up_vector(rng, direction)
        curves = operation_curves(solid, op, direction, rf)
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
        if hand == "people" and hidden_lines and rng.random() < P_HIDDEN_OUT:
            hidden_lines = False
        if not hidden_lines:
            if result_mesh is None:
                result_mesh = tessellate(
                    result.solid, MESH_REL_TOLERANCE * model_scale(result.solid)
                )
            curves = visible_curves(curves, camera, renderer.render(result_mesh, camera))
        if hand == "people":
            strokes, labels, ink = people_strokes(curves, camera, rng, noise_level)
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
