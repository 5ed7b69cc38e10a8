# SPDX-License-Identifier: LGPL-2.1-or-later
"""Generated samples: labels per operator, base face, context maps, view filter, determinism."""

import itertools

import numpy as np

from datagen.generate import MESH_REL_TOLERANCE, PER_CONTEXT, generate_block, generate_sample
from datagen.strokes import noise_sigma
from datagen.views import MIN_FACE_PIXELS, relevant_visibility
from Sketch2CADWorkbench.brep.faces import base_face_index, model_scale, resolve_face
from Sketch2CADWorkbench.brep.operators import apply_operation, replay
from Sketch2CADWorkbench.brep.protocol import OperatorType
from Sketch2CADWorkbench.render.mesh import tessellate
from Sketch2CADWorkbench.sketch.curves import operation_curves
from Sketch2CADWorkbench.sketch.labels import (
    BEVEL_L,
    BEVEL_L_PRIME,
    END,
    EXTRUDE_OFFSET,
    EXTRUDE_PROFILE,
    PROFILE,
    SHELL_RIM,
    SHELL_WALL,
    START,
)

LABELS = {
    OperatorType.EXTRUDE: {EXTRUDE_PROFILE, EXTRUDE_OFFSET},
    OperatorType.BEVEL: {BEVEL_L_PRIME, BEVEL_L},
    OperatorType.ADDSUB: {START, PROFILE, END},
    OperatorType.SWEEP: {START, PROFILE, END},
    OperatorType.SHELL: {SHELL_RIM},
}
# labels a sketch may hold besides: a shell's line down a wall is drawn now and then
MAY_HOLD = {OperatorType.SHELL: {SHELL_WALL}}


def _all(per_operator):
    return [s for samples in per_operator.values() for s in samples]


def _dense(polyline: np.ndarray, step: float = 0.5) -> np.ndarray:
    out = [
        np.linspace(a, b, max(int(np.linalg.norm(b - a) / step), 2))
        for a, b in itertools.pairwise(polyline)
    ]
    return np.concatenate(out)


def _distance_to(pixels_ij: tuple, polylines: list[np.ndarray]) -> np.ndarray:
    """Distance (px) of the pixel centres to the nearest of the polylines."""
    jj, ii = pixels_ij
    px = np.stack([ii + 0.5, jj + 0.5], axis=1)
    pts = np.concatenate([_dense(p) for p in polylines])
    return np.min(np.linalg.norm(px[:, None] - pts[None], axis=2), axis=1)


def test_each_operator_has_its_papers_label_set(per_operator):
    for kind, samples in per_operator.items():
        for s in samples:
            assert s.op_type is kind and s.operation.type is kind
            allowed = LABELS[kind] | MAY_HOLD.get(kind, set())
            assert LABELS[kind] <= set(s.stroke_parts) <= allowed
            on = s.stroke_mask > 0
            assert set(np.unique(s.curve_label[on])) <= allowed
            assert np.all(s.curve_label[~on] == 0) and np.array_equal(s.sketch, s.stroke_mask)


def test_stroke_pixels_lie_near_the_projection_of_their_labels_curves(per_operator):
    """E.g. for an extrusion, pixels labelled 1 are near the moved face's edges."""
    for s in _all(per_operator):
        context = replay(s.context)[-1]
        curves = operation_curves(context, s.operation, s.camera.direction)
        for label in set(s.stroke_parts):
            exact = [s.camera.project(c.points)[0] for c in curves if c.label == label]
            pixels = np.nonzero((s.stroke_mask > 0) & (s.curve_label == label))
            if len(pixels[0]) == 0:
                continue  # drawn over by other strokes
            near = _distance_to(pixels, exact)
            # level 1 moves end points by 5 px (RMS); the label's own curve is nearer
            # than its neighbours'.
            assert np.median(near) < 2 * noise_sigma(1, 256, 256), (s.op_type, label)


def test_extrude_offset_pixels_follow_the_moved_face_not_the_original(per_operator):
    for s in per_operator[OperatorType.EXTRUDE]:
        context = replay(s.context)[-1]
        rf = resolve_face(context, s.operation.face)
        edges = [
            np.array([e.positionAt(t).toTuple() for t in np.linspace(0, 1, 16)])
            for e in rf.face.Edges()
        ]
        moved = [s.camera.project(e + rf.normal * s.operation.d)[0] for e in edges]
        original = [s.camera.project(e)[0] for e in edges]
        pixels = np.nonzero((s.stroke_mask > 0) & (s.curve_label == EXTRUDE_OFFSET))
        assert np.median(_distance_to(pixels, moved)) < np.median(_distance_to(pixels, original))


def test_face_label_is_the_base_face_and_the_maps_show_the_context(per_operator, renderer):
    for s in _all(per_operator):
        context = replay(s.context)[-1]
        f = base_face_index(context, resolve_face(context, s.operation.face).face)
        assert s.face_label.sum() >= MIN_FACE_PIXELS
        assert np.array_equal(s.face_label > 0, s.face_id == f)
        mesh = tessellate(context, MESH_REL_TOLERANCE * model_scale(context))
        maps = renderer.render(mesh, s.camera)
        assert np.array_equal(maps.face_id, s.face_id)
        assert np.allclose(maps.depth, s.depth) and np.allclose(maps.normal, s.normal)


def test_the_relevant_curve_is_at_least_80_percent_visible(per_operator, renderer):
    for s in _all(per_operator):
        context = replay(s.context)[-1]
        curves = operation_curves(context, s.operation, s.camera.direction)
        against = (
            apply_operation(context, s.operation) if s.op_type is OperatorType.EXTRUDE else context
        )
        assert relevant_visibility(curves, s.camera, renderer.render(against, s.camera)) >= 0.8


def test_the_view_is_20_to_80_degrees_off_the_base_face_normal(per_operator):
    for s in _all(per_operator):
        cos = -np.dot(s.camera.direction, s.operation.face.normal)
        assert np.cos(np.radians(80.5)) < cos < np.cos(np.radians(19.5))


def test_samples_are_a_function_of_the_seed(renderer):
    a = generate_sample(np.random.default_rng(11), 2, renderer)
    b = generate_sample(np.random.default_rng(11), 2, renderer)
    assert a.operation == b.operation and a.context == b.context and a.camera == b.camera
    for name in ("sketch", "depth", "normal", "face_id", "curve_label"):
        assert np.array_equal(getattr(a, name), getattr(b, name))
    assert a.noise_level == 2


def test_a_block_shares_one_context_and_cycles_its_length(renderer):
    blocks = [generate_block(3, b, 1, renderer) for b in (0, 5)]
    for b, samples in zip((0, 5), blocks, strict=False):
        assert len(samples) == PER_CONTEXT
        assert len({s.context for s in samples}) == 1
        assert len(samples[0].context.operations) == b % 4
    again = generate_block(3, 5, 1, renderer)
    assert [s.operation for s in again] == [s.operation for s in blocks[1]]
    assert all(np.array_equal(x.sketch, y.sketch) for x, y in zip(again, blocks[1], strict=True))


def test_a_block_drawn_without_hidden_lines_shows_the_same_steps_with_less_ink(renderer):
    # a designer who draws only what is seen (sketch/visible.py): the same operations from
    # the same views, the lines the result hides left out
    every = generate_block(3, 5, 1, renderer)
    seen = generate_block(3, 5, 1, renderer, hidden_lines=False)
    assert [s.operation for s in seen] == [s.operation for s in every]
    assert [s.camera for s in seen] == [s.camera for s in every]
    assert sum(int(s.sketch.sum()) for s in seen) < sum(int(s.sketch.sum()) for s in every)
