# SPDX-License-Identifier: LGPL-2.1-or-later
"""Regular operations (`--regular-share`): set as a designer sets them, on what the
snapping snaps to; a share of 0 leaves the data as it was."""

import numpy as np
import pytest

from datagen.regular import GRID, on_grid
from datagen.sequences import Stage, is_regular, sample_operation, sample_sequence
from Sketch2CADWorkbench.brep.faces import FaceFrame
from Sketch2CADWorkbench.brep.operators import make_box, replay
from Sketch2CADWorkbench.brep.protocol import Box, OperatorType
from Sketch2CADWorkbench.brep.snap_targets import snap_targets

TOL = 1e-6


def _on_grid(x: float) -> bool:
    return abs(x / GRID - round(x / GRID)) < TOL


def _regular_length(x: float, earlier) -> bool:
    """On the grid, or equal to one of the `earlier` (size, name) pairs."""
    return _on_grid(abs(x)) or any(abs(abs(x) - s) < TOL for s, _ in earlier)


def _stages():
    """Stages to draw on: a box, and the last solid of two regular sequences."""
    yield Stage(make_box(Box((60.0, 50.0, 40.0))))
    for seed in (1, 2):
        yield sample_sequence(np.random.default_rng(seed), 2, regular_share=1.0).stages[-1]


def _drawn(kind: OperatorType, per_stage: int = 3):
    """(stage, drawn operation, f's frame, snap targets) of regular operations."""
    rng = np.random.default_rng(11)
    for stage in _stages():
        for _ in range(per_stage):
            drawn = sample_operation(rng, stage, kind, regular_share=1.0)
            if drawn is None:
                continue
            frame = FaceFrame.of(drawn.face.face)
            yield stage, drawn, frame, snap_targets(stage.solid, drawn.face.face, frame)


def _regular_centre(c: np.ndarray, targets) -> bool:
    """c (2D) on f's centre, on an earlier round feature's axis, or on a centre line a
    whole number of grid steps from the centre."""
    if any(
        np.linalg.norm(c - p) < TOL
        for p, name in targets.points
        if name in ("the face's centre", "the axis of an earlier round feature")
    ):
        return True
    for _, d, name in targets.lines + [(None, a, "an axis") for a in targets.axes]:
        if name in ("the face's centre line", "an axis"):
            off = c - targets.origin
            if abs(off[0] * d[1] - off[1] * d[0]) < TOL and _on_grid(off @ d):
                return True
    return False


def test_on_grid_rounds_to_whole_steps_and_never_to_zero():
    assert on_grid(12.4) == 12.0 and on_grid(12.6) == 13.0 and on_grid(0.2) == GRID


def test_a_share_of_0_draws_nothing_so_the_data_is_unchanged():
    a, b = np.random.default_rng(5), np.random.default_rng(5)
    assert not is_regular(a, 0.0)
    assert a.random() == b.random()  # the generator did not move
    assert (
        sample_sequence(np.random.default_rng(9), 3, regular_share=0.0).protocol
        == sample_sequence(np.random.default_rng(9), 3).protocol
    )


def test_the_share_decides_how_many_operations_are_regular():
    rng = np.random.default_rng(0)
    got = np.mean([is_regular(rng, 0.3) for _ in range(4000)])
    assert got == pytest.approx(0.3, abs=0.03)


def test_regular_prisms_are_aligned_rectangles_or_regular_polygons_placed_regularly():
    seen = 0
    for _stage, drawn, frame, targets in _drawn(OperatorType.ADDSUB):
        poly = frame.to_2d(np.array(drawn.op.polygon))
        sides = np.roll(poly, -1, axis=0) - poly
        lengths = np.linalg.norm(sides, axis=1)
        first = sides[0] / lengths[0]
        e1 = targets.axes[0]
        assert abs(first[0] * e1[1] - first[1] * e1[0]) < TOL  # a side along f's edge
        if len(poly) == 4 and np.allclose(sides[0] @ sides[1], 0, atol=TOL):
            assert all(_regular_length(s, targets.sizes) for s in lengths[:2])
        else:
            assert np.allclose(lengths, lengths[0]) and _on_grid(lengths[0])
        assert _regular_centre(poly.mean(axis=0), targets)
        assert _regular_length(drawn.op.d, targets.sizes)
        seen += 1
    assert seen >= 6


def test_regular_sweeps_are_straight_with_regular_radii_and_place():
    seen = 0
    for _stage, drawn, frame, targets in _drawn(OperatorType.SWEEP):
        op = drawn.op
        chord = [[op.r0 + (op.r1 - op.r0) * k / 3, op.d * k / 3] for k in (1, 2)]
        assert np.allclose(op.profile, chord)
        assert _regular_length(op.r0, targets.radii) and _regular_length(op.r1, targets.radii)
        assert _regular_length(op.d, targets.sizes)
        assert _regular_centre(frame.to_2d(np.array(op.center))[0], targets)
        seen += 1
    assert seen >= 6


def test_regular_extrusions_and_bevels_use_regular_lengths():
    for _stage, drawn, _frame, targets in _drawn(OperatorType.EXTRUDE):
        assert _regular_length(drawn.op.d, targets.sizes)
    for _stage, drawn, _frame, _targets in _drawn(OperatorType.BEVEL):
        p = np.array(drawn.op.profile)
        spans = np.linalg.norm(p[[0, 3]] - np.array(drawn.op.corner), axis=1)
        assert spans[0] == pytest.approx(spans[1]) and _on_grid(spans[0])


def test_regular_sequences_replay_to_valid_solids():
    for seed in range(3):
        seq = sample_sequence(np.random.default_rng(seed), 3, regular_share=1.0)
        solids = replay(seq.protocol)
        assert all(len(s.Solids()) == 1 and s.isValid() for s in solids)
