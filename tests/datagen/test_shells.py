# SPDX-License-Identifier: LGPL-2.1-or-later
"""Shell samples: drawn only where asked for, labelled with the opened face and the rim."""

import numpy as np
import pytest

from datagen.generate import (
    WALL_SPAN,
    Context,
    generate_block,
    last_op_weights,
    sample_on,
    wall_curve,
)
from datagen.parallel import DatagenSettings, manifest_of
from datagen.sequences import LAST_OP_WEIGHTS, draw_type, sample_sequence
from Sketch2CADWorkbench.brep.faces import resolve_face
from Sketch2CADWorkbench.brep.operators import apply_operation, build, make_box
from Sketch2CADWorkbench.brep.protocol import Box, FaceRef, OperatorType, Shell
from Sketch2CADWorkbench.sketch.labels import SHELL_RIM, SHELL_WALL


def test_a_type_of_weight_0_changes_no_draw():
    four = {t: w for t, w in LAST_OP_WEIGHTS.items() if t is not OperatorType.SHELL}
    a, b = np.random.default_rng(3), np.random.default_rng(3)
    assert [draw_type(a) for _ in range(200)] == [draw_type(b, four) for _ in range(200)]
    assert a.random() == b.random()  # and the generators stand at the same state


@pytest.mark.slow
def test_shells_are_drawn_only_where_asked_for(renderer):
    kinds = {s.op_type for b in range(2) for s in generate_block(11, b, 1, renderer)}
    assert OperatorType.SHELL not in kinds
    assert last_op_weights(True)[OperatorType.SHELL] == LAST_OP_WEIGHTS[OperatorType.SWEEP]
    plain = manifest_of(DatagenSettings(out=None, count=4), [])
    assert "shells" not in plain  # a set made without shells has the manifest it had
    assert manifest_of(DatagenSettings(out=None, count=4, shells=True), [])["shells"] is True


@pytest.fixture(scope="module")
def shell_samples(renderer):
    return [
        sample_on(
            Context(sample_sequence(np.random.default_rng([40, n]), n)),
            np.random.default_rng([40, n, 1]),
            1,
            renderer,
            kind=OperatorType.SHELL,
        )
        for n in range(4)
    ]


@pytest.mark.slow
def test_a_shell_sample_labels_the_opened_face_and_the_rim(shell_samples):
    for s in shell_samples:
        assert s.op_type is OperatorType.SHELL and isinstance(s.operation, Shell)
        context = build(s.context)
        face = context.Faces().index(resolve_face(context, s.operation.face).face)
        assert np.array_equal(s.face_label > 0, s.face_id == face)
        assert s.stroke_parts.count(SHELL_WALL) <= 1
        assert s.stroke_parts.count(SHELL_RIM) >= 1
        assert set(s.stroke_parts) <= {SHELL_RIM, SHELL_WALL}


def test_the_line_down_a_wall_starts_at_a_rim_corner_and_stays_in_the_cavity():
    box = make_box(Box((60.0, 40.0, 30.0)))
    top = FaceRef((0.0, 0.0, 15.0), (0.0, 0.0, 1.0))
    op = Shell(top, 3.0)
    shelled = apply_operation(box, op)
    rf = resolve_face(box, top)
    corners = {(x, y) for x in (-27.0, 27.0) for y in (-17.0, 17.0)}
    for seed in range(5):
        wall = wall_curve(np.random.default_rng(seed), shelled, rf, op)
        (x, y, z), bottom = wall.points
        assert (round(x, 6), round(y, 6)) in corners and z == pytest.approx(15.0)
        depth = z - bottom[2]  # the cavity is 27 mm deep
        assert WALL_SPAN[0] * 27 - 1e-6 <= depth <= WALL_SPAN[1] * 27 + 1e-6
        assert np.allclose(bottom[:2], (x, y)) and wall.label == SHELL_WALL
