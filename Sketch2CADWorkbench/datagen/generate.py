# SPDX-License-Identifier: LGPL-2.1-or-later
"""One synthetic sample: a random sequence, a view of its last operation, strokes, labels."""
from __future__ import annotations

import numpy as np

from ..brep.faces import resolve_face
from ..brep.protocol import OperatorType, Protocol
from ..render.camera import OrthoCamera
from ..render.maps import MapRenderer
from ..render.mesh import tessellate
from ..render.strokes import rasterize
from ..render.visibility import visible_fraction
from .curves import operation_curves
from .sample import Sample
from .sequences import draw_type, sample_operation, sample_sequence
from .strokes import noise_sigma, perturb
from .views import MAX_OCCLUSION, SCALE_RANGE, frame_curves, up_vector, view_direction

IMAGE_SIZE = 256
VIEW_TRIES = 8
# Samples sharing one context sequence: the paper makes 40k shapes from 10k protocols,
# and building the context is most of a sample's cost.
PER_CONTEXT = 4


def sample_rng(seed: int, index: int, stream: int = 0) -> np.random.Generator:
    """The generator of item `index` of a data set: independent of worker and order.

    Stream 0 draws samples, stream 1 draws the shared context sequences.
    """
    return np.random.default_rng(np.random.SeedSequence([seed, stream, index]))


def generate_block(seed: int, block: int, noise_level: int, renderer: MapRenderer,
                   size: int = IMAGE_SIZE) -> list[Sample]:
    """Samples block*PER_CONTEXT ... block*PER_CONTEXT + PER_CONTEXT-1 (deterministic).

    A block shares one context sequence (drawn from the block's own generator); each
    sample draws its own last operation (1:1:4:2) and view from its own generator.
    Sequence lengths cycle through 1..4 with the block, so they are balanced. A last
    operation with no unoccluded view is drawn again.
    """
    length = 1 + block % 4
    shared = sample_sequence(sample_rng(seed, block, stream=1), length - 1)
    out = []
    for index in range(block * PER_CONTEXT, (block + 1) * PER_CONTEXT):
        rng = sample_rng(seed, index)
        kind = draw_type(rng)
        seq = shared
        while True:
            got = sample_operation(rng, seq.solids[-1], kind)
            if got is None:  # this context admits no such operation: a fresh one
                seq = sample_sequence(rng, length - 1)
                continue
            sample = _view_sample(rng, seq.protocol.append(got[0]), seq.solids[-1], got[1],
                                  noise_level, renderer, size)
            if sample is not None:
                out.append(sample)
                break
    return out


def _view_sample(rng, protocol: Protocol, context, result, noise_level, renderer, size):
    """A sample of the last operation seen from a random informative view, or None when
    VIEW_TRIES views all hide too much of the relevant curve.

    The relevant curve must be at least 80% visible: for an extrusion the offset curve,
    seen against the result (a pocket's floor is inside the context solid); for the
    other operators the base curve on f, seen against the context (the new primitive
    itself always hides part of its own base).
    """
    op = protocol.operations[-1]
    rf = resolve_face(context, op.face)
    face_index = next(i for i, f in enumerate(context.Faces()) if f.isSame(rf.face))
    context_mesh = tessellate(context)
    result_mesh = tessellate(result) if op.type is OperatorType.EXTRUDE else None
    for _ in range(VIEW_TRIES):
        direction = view_direction(rng, rf.normal)
        probe = OrthoCamera((0.0, 0.0, 0.0), tuple(direction), up_vector(direction), 1.0,
                            size, size)
        curves = operation_curves(context, op, probe)
        pts = np.concatenate([c.points for c in curves])
        camera = frame_curves(pts, direction, rng.uniform(*SCALE_RANGE), size)
        base_pts = np.concatenate([c.points for c in curves if c.base])
        maps = renderer.render(context_mesh, camera)
        seen = maps if result_mesh is None else renderer.render(result_mesh, camera)
        if visible_fraction(base_pts, camera, seen, 2 * camera.pixel_size) < 1 - MAX_OCCLUSION:
            continue
        sigma = noise_sigma(noise_level, size, size)
        strokes = [perturb(camera.project(c.points)[0], rng, sigma, c.closed) for c in curves]
        labels = [c.label for c in curves]
        order = rng.permutation(len(strokes))  # designers draw in any order
        strokes, labels = [strokes[i] for i in order], [labels[i] for i in order]
        sketch = rasterize(strokes, size, size)
        return Sample(
            op_type=op.type, sketch=sketch, depth=maps.depth, normal=maps.normal,
            face_id=maps.face_id, face_label=(maps.face_id == face_index).astype(np.float32),
            curve_label=rasterize(strokes, size, size, [float(l) for l in labels]),
            stroke_mask=sketch.copy(), context=Protocol(protocol.base, protocol.operations[:-1]),
            operation=op, camera=camera, strokes=strokes, stroke_parts=labels,
            noise_level=noise_level)
    return None
