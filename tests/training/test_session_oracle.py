# SPDX-License-Identifier: LGPL-2.1-or-later
"""The session oracle: a step's numbers read by least squares on the strokes that draw
its curves, and a session's end as those readings make it."""

import pytest
from session_fixtures import BASE, BOSS, POST, TOP, sketched_step

from Sketch2CADWorkbench.brep.operators import replay
from Sketch2CADWorkbench.brep.protocol import AddSubPrism, Extrude, FaceRef, Protocol
from Sketch2CADWorkbench.inference.options import InterpretOptions
from Sketch2CADWorkbench.inference.session import Session
from training.session_oracle import oracle_reading, session_oracle


def test_exact_strokes_read_exactly():
    protocol = Protocol(BASE, [POST])
    got = oracle_reading(replay(protocol)[0], POST, sketched_step(protocol, 0))
    assert got.iou == pytest.approx(1.0, abs=1e-6)
    assert got.rms_px < 1e-3 and got.truth_rms_px < 1e-3
    assert got.strokes == 12  # base outline, far outline, side edges


def test_what_the_strokes_draw_is_read_not_what_the_protocol_says():
    protocol = Protocol(BASE, [Extrude(TOP, 4.0)])
    got = oracle_reading(
        replay(protocol)[0],
        protocol.operations[0],
        sketched_step(protocol, 0, drawn_as=Extrude(TOP, 6.0)),
    )
    assert got.reading.d == pytest.approx(6.0, abs=1e-3)
    assert got.iou == pytest.approx(24.0 / 26.0, abs=1e-3)  # box 20 high: 24 / 26 mm
    assert got.truth_rms_px > 1.0 > got.rms_px


def test_a_noisy_hand_is_read_no_farther_from_its_strokes_than_the_truth():
    protocol = Protocol(BASE, [POST, BOSS])
    for k, op in enumerate(protocol.operations):
        got = oracle_reading(replay(protocol)[k], op, sketched_step(protocol, k, sigma=4.0, seed=k))
        assert got.rms_px <= got.truth_rms_px + 1e-9
        assert 0.5 < got.iou < 1.0  # the hand moved it, a little


def test_snapping_as_the_step_chooses_puts_a_near_reading_on_the_grid():
    protocol = Protocol(BASE, [Extrude(TOP, 4.0)])
    step = sketched_step(
        protocol,
        0,
        drawn_as=Extrude(TOP, 4.2),
        choices=InterpretOptions(regularize=True, snap_step=1.0),
    )
    got = oracle_reading(replay(protocol)[0], protocol.operations[0], step)
    assert got.reading.d == pytest.approx(4.2, abs=1e-3)
    assert got.snapped.d == pytest.approx(4.0) and got.snapped_iou == pytest.approx(1.0)


def test_a_session_ends_where_the_readings_together_build_it():
    protocol = Protocol(BASE, [POST, BOSS])
    exact = Session(BASE, [sketched_step(protocol, k) for k in range(2)])
    assert session_oracle(exact, protocol).final_iou == pytest.approx(1.0, abs=1e-6)
    taller = Protocol(BASE, [AddSubPrism(POST.face, POST.polygon, 16.0), BOSS])
    drawn = Session(BASE, [sketched_step(taller, 0), sketched_step(protocol, 1)])
    got = session_oracle(drawn, protocol)
    assert got.steps[0].reading.d == pytest.approx(16.0, abs=1e-3)
    assert got.final_iou < 0.99  # the post drawn 4 mm taller
    with pytest.raises(ValueError, match="2 steps and the protocol 1 operations"):
        session_oracle(drawn, Protocol(BASE, [POST]))


def test_the_step_whose_strokes_bound_the_session_is_named_with_where_it_ends_it():
    protocol = Protocol(BASE, [POST, BOSS])
    taller = Protocol(BASE, [AddSubPrism(POST.face, POST.polygon, 16.0), BOSS])
    got = session_oracle(
        Session(BASE, [sketched_step(taller, 0), sketched_step(protocol, 1)]), protocol
    )
    first, second = got.steps
    assert second.session_iou == pytest.approx(1.0, abs=1e-6)  # drawn exactly
    assert first.session_iou < 0.99 and first.snapped_session_iou == first.session_iou
    assert got.weakest == (1, pytest.approx(first.session_iou))
    # the boss alone was exact, so the post alone ends the session where both do
    assert first.session_iou == pytest.approx(got.final_iou, abs=1e-6)


def test_an_extruded_rim_drawn_as_a_loop_counts_with_the_strokes():
    boss_top = FaceRef((-2.0, 1.0, 30.0), (0.0, 0.0, 1.0))
    protocol = Protocol(BASE, [POST, BOSS, Extrude(boss_top, 3.0)])
    got = oracle_reading(
        replay(protocol)[2],
        protocol.operations[2],
        sketched_step(protocol, 2, drawn_as=Extrude(boss_top, 5.0)),
    )
    assert got.strokes == 1  # the rim: a polyline back to its start
    assert got.reading.d == pytest.approx(5.0, abs=1e-3)
