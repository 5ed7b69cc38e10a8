# SPDX-License-Identifier: LGPL-2.1-or-later
"""A reading's SketchFit: the operation that was drawn explains its strokes best."""

import numpy as np
import pytest

from Sketch2CADWorkbench.brep.operators import make_box
from Sketch2CADWorkbench.brep.protocol import Box, FaceRef, Mode, Sweep
from Sketch2CADWorkbench.inference.fitting.verify import (
    DrawnStrokes,
    SketchFit,
    end_gaps,
    sketch_fit,
)
from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.sketch.curves import operation_curves

TOP = FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0))


def sweep(r1: float, d: float) -> Sweep:
    return Sweep(TOP, (2.0, 0.0, 10.0), 5.0, r1, d, ((5.0, d / 3), (r1, 2 * d / 3)), Mode.ADD)


def drawn_sweep():
    """A box, a view of it, and a sweep on its top drawn exactly as its own sketch."""
    box = make_box(Box((40, 30, 20)))
    d = np.array([0.6, 0.9, -1.2])
    cam = OrthoCamera((0.0, 0.0, 5.0), tuple(d / np.linalg.norm(d)), (0, 0, 1), 45.0, 800, 600)
    drawn = sweep(4.0, 10.0)
    return (
        box,
        cam,
        drawn,
        [cam.project(c.points)[0] for c in operation_curves(box, drawn, cam.direction)],
    )


def test_the_drawn_sweep_explains_its_strokes_better_than_a_longer_wider_one():
    box, cam, drawn, strokes = drawn_sweep()
    exact = sketch_fit(box, drawn, cam, strokes).misfit_px
    assert exact == pytest.approx(0.0, abs=1.0)
    assert sketch_fit(box, sweep(9.0, 16.0), cam, strokes).misfit_px > exact + 5.0


def test_seen_lines_tell_a_hole_from_the_boss_on_its_rim_that_draws_the_same_lines():
    # paper, Fig. 5b: the boss stands on the hole's floor outline slid along the view onto
    # f, so its top outline is the rim; drawn with every line the two read alike, drawn
    # as seen (hidden lines left out) only the hole explains the strokes
    from Sketch2CADWorkbench.brep.operators import apply_operation
    from Sketch2CADWorkbench.brep.protocol import AddSubPrism
    from Sketch2CADWorkbench.render.maps import MapRenderer
    from Sketch2CADWorkbench.sketch.visible import visible_curves

    renderer = MapRenderer()
    box = make_box(Box((40, 30, 20)))
    v = np.array([0.3, 0.8, -1.0]) / np.linalg.norm([0.3, 0.8, -1.0])
    cam = OrthoCamera((0.0, 0.0, 5.0), tuple(v), (0, 0, 1), 45.0, 512, 512)
    rim = np.array([(-5.0, -5.0, 10.0), (5.0, -5.0, 10.0), (5.0, 5.0, 10.0), (-5.0, 5.0, 10.0)])
    hole = AddSubPrism(TOP, tuple(map(tuple, rim)), 6.0, Mode.SUBTRACT)
    floor_on_f = rim - (0, 0, 6.0) - v * (6.0 / -v[2])  # back up along the view onto f
    boss = AddSubPrism(TOP, tuple(map(tuple, floor_on_f)), 6.0, Mode.ADD)
    every = [cam.project(c.points)[0] for c in operation_curves(box, hole, cam.direction)]
    assert sketch_fit(box, boss, cam, every).misfit_px == pytest.approx(0.0, abs=0.5)
    maps = {op: renderer.render(apply_operation(box, op), cam) for op in (hole, boss)}
    drawn = [
        cam.project(c.points)[0]
        for c in visible_curves(operation_curves(box, hole, cam.direction), cam, maps[hole])
    ]
    assert sketch_fit(box, hole, cam, drawn, maps[hole]).misfit_px == pytest.approx(0.0, abs=0.5)
    assert sketch_fit(box, boss, cam, drawn, maps[boss]).misfit_px > 3.0


def test_strokes_scored_once_for_many_readings_score_them_as_the_strokes_themselves():
    box = make_box(Box((40, 30, 20)))
    d = np.array([0.6, 0.9, -1.2])
    cam = OrthoCamera((0.0, 0.0, 5.0), tuple(d / np.linalg.norm(d)), (0, 0, 1), 45.0, 800, 600)
    strokes = [
        cam.project(c.points)[0] for c in operation_curves(box, sweep(4.0, 10.0), cam.direction)
    ]
    drawn = DrawnStrokes(strokes, (cam.height, cam.width))
    for op in (sweep(4.0, 10.0), sweep(9.0, 16.0)):
        got, want = sketch_fit(box, op, cam, drawn), sketch_fit(box, op, cam, strokes)
        for name in ("to_sketch", "to_strokes", "end_gaps"):
            np.testing.assert_array_equal(getattr(got, name), getattr(want, name))


def test_the_misfit_weighs_both_ways_alike_however_many_samples_each_has():
    fit = SketchFit(np.array([1.0, 1.0, 1.0, 5.0]), np.array([4.0]), np.zeros(0))
    assert fit.misfit_px == 3.0 and (fit.strokes_off_px, fit.sketch_off_px) == (2.0, 4.0)


def test_a_sketch_that_cannot_be_drawn_fits_nothing():
    assert SketchFit.undrawn().misfit_px == np.inf


def test_the_strokes_ends_are_scored_against_the_ends_of_the_curves_they_draw():
    curves = [np.array([[0.0, 0.0], [5.0, 0.0], [10.0, 0.0]]), np.array([[0.0, 5.0], [0.0, 20.0]])]
    strokes = [np.array([[0.0, 21.0], [0.0, 6.0]]), np.array([[1.0, 0.0], [5.0, 0.5], [11.0, 1.0]])]
    gaps = end_gaps(curves, DrawnStrokes(strokes, (40, 40)).open_ends)
    assert sorted(np.round(gaps, 6)) == sorted(np.round([1.0, 1.0, 1.0, np.sqrt(2)], 6))


def test_a_reading_whose_lines_run_past_the_strokes_ends_scores_worse_however_close():
    # a reading along a displaced stroke lies closer to it (0 px for 2) but runs 200 px
    # past its end: ranked by closeness plus the end gaps, the one meant comes first
    meant = SketchFit(np.full(50, 2.0), np.full(10, 2.0), np.array([2.0, 2.0]))
    along = SketchFit(np.zeros(50), np.r_[np.zeros(10), np.full(10, 50.0)], np.array([0.0, 200.0]))
    assert meant.score < along.score
    no_ends = SketchFit(meant.to_sketch, meant.to_strokes, np.zeros(0))
    assert no_ends.score == meant.misfit_px == 2.0


def test_a_sketch_is_scored_by_its_closeness_both_ways_and_its_end_gaps():
    box, cam, drawn, strokes = drawn_sweep()
    ends = sketch_fit(box, drawn, cam, strokes).end_gaps
    assert len(ends) == 4 and np.all(ends < 1e-6)  # the two profile lines' ends; circles none
