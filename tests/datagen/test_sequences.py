# SPDX-License-Identifier: LGPL-2.1-or-later
"""Random sequences: valid, deterministic, with the paper's type frequencies and sizes."""

import itertools

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from datagen.operations import DIAG, PlanarFace, change_bound, random_centre, random_polygon
from datagen.sequences import (
    MIN_VOLUME_CHANGE,
    Stage,
    draw_type,
    random_box,
    sample_operation,
    sample_sequence,
)
from Sketch2CADWorkbench.brep.operators import apply_operation, make_box, replay
from Sketch2CADWorkbench.brep.protocol import Box, Mode, OperatorType


@settings(max_examples=8, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.integers(0, 2**32 - 1), st.integers(1, 4))
def test_every_sampled_protocol_replays_to_one_valid_solid(seed, length):
    seq = sample_sequence(np.random.default_rng(seed), length)
    assert len(seq.protocol.operations) == length
    solids = replay(seq.protocol)
    for before, after in itertools.pairwise(solids):
        assert len(after.Solids()) == 1 and after.isValid()
        assert abs(after.Volume() - before.Volume()) >= MIN_VOLUME_CHANGE * before.Volume()
    assert solids[-1].Volume() == pytest.approx(seq.stages[-1].volume, rel=1e-9)


def test_sequences_are_a_function_of_the_generator_seed():
    a = sample_sequence(np.random.default_rng(7), 3)
    b = sample_sequence(np.random.default_rng(7), 3)
    assert a.protocol == b.protocol


def test_boxes_have_a_100_mm_diagonal_and_varied_aspect():
    rng = np.random.default_rng(0)
    sizes = np.array([random_box(rng).size for _ in range(200)])
    assert np.allclose(np.linalg.norm(sizes, axis=1), DIAG, rtol=1e-4)
    aspect = sizes.max(axis=1) / sizes.min(axis=1)
    assert aspect.min() < 1.3 and aspect.max() > 2.2


def test_last_operation_types_follow_1_1_4_2():
    rng = np.random.default_rng(1)
    draws = [draw_type(rng) for _ in range(8000)]
    share = {t: draws.count(t) / len(draws) for t in OperatorType}
    for t, expected in (
        (OperatorType.EXTRUDE, 1 / 8),
        (OperatorType.BEVEL, 1 / 8),
        (OperatorType.ADDSUB, 4 / 8),
        (OperatorType.SWEEP, 2 / 8),
    ):
        assert share[t] == pytest.approx(expected, abs=0.02)


def _cross(u, v):
    return u[0] * v[1] - u[1] * v[0]


def test_random_polygons_never_cross_themselves():
    rng = np.random.default_rng(2)
    for _ in range(300):
        k = int(rng.integers(3, 7))
        q = random_polygon(rng, k, 10.0)
        assert q.shape == (k, 2)
        for i in range(k):
            for j in range(i + 2, k):
                if (i, j) == (0, k - 1):
                    continue
                a, b, c, d = q[i], q[(i + 1) % k], q[j], q[(j + 1) % k]
                o = [
                    _cross(b - a, c - a),
                    _cross(b - a, d - a),
                    _cross(d - c, a - c),
                    _cross(d - c, b - c),
                ]
                assert not (o[0] * o[1] < 0 and o[2] * o[3] < 0)


def test_the_change_bound_is_never_below_the_actual_volume_change():
    rng = np.random.default_rng(3)
    stage = Stage(make_box(Box((60.0, 50.0, 40.0))))
    for kind in list(OperatorType) * 3:
        drawn = sample_operation(rng, stage, kind)
        assert drawn is not None
        change = abs(drawn.result.volume - stage.volume)
        assert change_bound(drawn.op, drawn.face) >= change * (1 - 1e-6)
        assert drawn.result.solid.Volume() == pytest.approx(
            apply_operation(stage.solid, drawn.op).Volume()
        )


def test_sampled_operations_stand_on_the_face_they_name():
    rng = np.random.default_rng(4)
    stage = Stage(make_box(Box((60.0, 50.0, 40.0))))
    for kind in list(OperatorType) * 2:
        drawn = sample_operation(rng, stage, kind)
        assert isinstance(drawn.face, PlanarFace)
        assert drawn.op.type is kind and drawn.op.face == drawn.face.ref


def test_random_centres_keep_their_margin_from_the_face_edges():
    box = make_box(Box((40.0, 30.0, 20.0)))
    top = next(f for f in box.Faces() if f.Center().z > 9.0)
    f = PlanarFace(top, np.array([0.0, 0.0, 1.0]))
    assert f.edge_distance(np.array([0.0, 0.0, 10.0])) == pytest.approx(15.0)
    rng = np.random.default_rng(0)
    centres = [c for c in (random_centre(f, rng, 10.0) for _ in range(20)) if c is not None]
    assert len(centres) >= 15  # a sixth of the face qualifies; 30 draws each
    c = np.array(centres)
    assert (np.abs(c[:, 0]) <= 10.0 + 1e-9).all() and (np.abs(c[:, 1]) <= 5.0 + 1e-9).all()
    assert f.edge_distance(np.array([19.0, 0.0, 10.0])) == pytest.approx(1.0)  # kept, not stale


def test_an_operation_drawn_with_a_condition_meets_it_and_builds():
    stage = Stage(make_box(Box((60.0, 50.0, 40.0))))
    for seed in range(4):
        drawn = sample_operation(
            np.random.default_rng(seed),
            stage,
            OperatorType.SWEEP,
            keep=lambda op: op.mode is Mode.SUBTRACT,
        )
        assert drawn.op.mode is Mode.SUBTRACT
        assert drawn.result.volume < stage.volume * (1 - MIN_VOLUME_CHANGE)
