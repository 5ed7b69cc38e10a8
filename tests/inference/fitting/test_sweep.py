# SPDX-License-Identifier: LGPL-2.1-or-later
"""Sweep fitting recovers the cone, cylinder or curved profile that produced the strokes."""

import numpy as np
import pytest
from fit_sketches import TOP_Z, face_towards, sweep_sketch

from Sketch2CADWorkbench.brep.operators import apply_operation
from Sketch2CADWorkbench.brep.protocol import Mode
from Sketch2CADWorkbench.inference.fitting import sweep as sweep_fitting
from Sketch2CADWorkbench.inference.fitting.common import FitError
from Sketch2CADWorkbench.inference.fitting.sweep import fit_sweep


def test_sweep_fit_recovers_a_cone(box, camera):
    strokes, labels = sweep_sketch(camera, (4, -2, TOP_Z), 6.0, 3.0, 10.0, +1)
    op = fit_sweep(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)
    assert op.mode is Mode.ADD
    assert op.center == pytest.approx((4, -2, TOP_Z), abs=0.15)
    assert (op.r0, op.r1, op.d) == pytest.approx((6.0, 3.0, 10.0), abs=0.2)


def test_sweep_fit_recovers_a_curved_profile(box, camera):
    prof = [(5.0, 0.0), (9.0, 3.0), (2.0, 7.0), (4.0, 10.0)]
    strokes, labels = sweep_sketch(camera, (2, 0, TOP_Z), 5.0, 4.0, 10.0, +1, prof)
    op = fit_sweep(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)
    assert np.array(op.profile) == pytest.approx(np.array(prof[1:3]), abs=0.6)


def test_a_profile_stroke_that_swings_far_outside_the_circles_is_not_taken_as_drawn(box, camera):
    strokes, labels = sweep_sketch(camera, (2, 0, TOP_Z), 5.0, 4.0, 10.0, +1)
    wild = [(5.0, 0.0), (40.0, -30.0), (-20.0, 45.0), (4.0, 10.0)]  # r, h far out
    swinging, _ = sweep_sketch(camera, (2, 0, TOP_Z), 5.0, 4.0, 10.0, +1, wild)
    strokes[2:] = swinging[2:]  # the circles as drawn, the profiles swinging out
    op = fit_sweep(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)
    (r1, h1), (r2, h2) = op.profile
    assert 0 <= h1 <= h2 <= 10.0 + 1e-6 and 0 < max(r1, r2) <= 10.0


def test_a_profile_read_a_little_past_the_far_circle_stays_between_the_circles(
    box, camera, monkeypatch
):
    # test-l1 (seed 10001) sample 263: a profile stroke back-projected to control heights
    # a few % past d (within the slack that keeps drawn profiles) folded the surface of
    # revolution back over the far circle, and OCCT called the result invalid
    strokes, labels = sweep_sketch(camera, (2, 0, TOP_Z), 5.0, 4.0, 10.0, +1)
    fit = sweep_fitting.fit_bezier
    monkeypatch.setattr(
        sweep_fitting,
        "fit_bezier",
        lambda rh, a, b: (
            fit(rh, a, b) + np.array([[0.0, 0.0], [0.0, -3.8], [0.0, 3.9], [0.0, 0.0]])
        ),
    )  # h1 below 0, h2 past d
    op = fit_sweep(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)
    heights = np.array(op.profile)[:, 1]
    assert np.all((heights >= 0) & (heights <= op.d)) and heights.max() == pytest.approx(op.d)
    apply_operation(box, op)  # one valid solid (raises otherwise)


def test_a_tail_the_hand_leaves_on_a_circle_does_not_pull_the_sweep_off(box, camera):
    strokes, labels = sweep_sketch(camera, (4, -2, TOP_Z), 6.0, 3.0, 10.0, +1)
    # the far circle drawn on past its start: a 4 mm tail leaving it tangentially, which
    # pulls a free ellipse fitted to that stroke alone (r1 2.85, d 10.22)
    t = np.linspace(0, 2 * np.pi, 72)
    ring = np.stack([4 + 3 * np.cos(t), -2 + 3 * np.sin(t), np.full_like(t, TOP_Z + 10)], 1)
    tail = ring[-1] + np.linspace(0, 4.0, 20)[1:, None] * np.array([0.0, 1.0, 0.0])
    strokes[labels.index(2)] = camera.project(np.vstack([ring, tail]))[0]
    op = fit_sweep(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)
    assert op.center == pytest.approx((4, -2, TOP_Z), abs=0.05)
    assert (op.r0, op.r1, op.d) == pytest.approx((6.0, 3.0, 10.0), abs=0.06)


def test_deep_hole_is_read_as_a_subtraction(box, camera):
    strokes, labels = sweep_sketch(camera, (0, 0, TOP_Z), 4.0, 4.0, 16.0, -1)
    op = fit_sweep(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)
    assert op.mode is Mode.SUBTRACT and op.d == pytest.approx(16.0, abs=0.3)


def test_sweep_without_its_far_circle_is_refused(box, camera):
    strokes, labels = sweep_sketch(camera, (0, 0, TOP_Z), 4.0, 4.0, 8.0, +1)
    with pytest.raises(FitError, match="both circle outlines"):
        fit_sweep(
            box,
            face_towards(box, (0, 0, 1)),
            camera,
            strokes[:1] + strokes[2:],
            labels[:1] + labels[2:],
        )


def test_a_hole_drawn_with_only_part_of_its_floor_circle_is_read_from_its_rim(box, camera):
    # a designer leaves out the floor circle's near part, which the hole's material hides
    strokes, labels = sweep_sketch(camera, (2, 0, TOP_Z), 5.0, 5.0, 8.0, -1)
    floor = strokes[0]
    strokes[0] = floor[: len(floor) // 3]  # a third of the floor's loop
    # which Boolean is the search's to weigh (inference/alternative.py): here the hole's
    op = fit_sweep(box, face_towards(box, (0, 0, 1)), camera, strokes, labels, Mode.SUBTRACT)
    assert op.center == pytest.approx((2, 0, TOP_Z), abs=0.3)
    assert (op.r0, op.r1, op.d) == pytest.approx((5.0, 5.0, 8.0), abs=0.4)
