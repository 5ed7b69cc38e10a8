# SPDX-License-Identifier: LGPL-2.1-or-later
"""A hand that draws as people do: outlines in one stroke, curves in parts, loops open."""

import numpy as np

from datagen.hand import HABITS, habits_of, join_end_to_start, people_strokes
from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.sketch.curves import Curve
from Sketch2CADWorkbench.sketch.segment import distances_to, segment_strokes

CAMERA = OrthoCamera((0.0, 0.0, 0.0), (0.0, 0.0, -1.0), (0.0, 1.0, 0.0), 50.0)
SQUARE = [(-30.0, -30.0), (30.0, -30.0), (30.0, 30.0), (-30.0, 30.0)]


def square_sides(label: int = 0) -> list[Curve]:
    return [
        Curve(np.array([[*a, 0.0], [*b, 0.0]]), label)
        for a, b in zip(SQUARE, SQUARE[1:] + SQUARE[:1], strict=False)
    ]


def test_people_draw_outlines_in_fewer_strokes_and_curves_in_parts():
    counts = [
        len(people_strokes(square_sides(), CAMERA, np.random.default_rng(k), 1)[0])
        for k in range(60)
    ]
    assert min(counts) < 4  # a square's outline in one go, or in two L shapes
    assert max(counts) > 4  # a side split or traced over


def test_the_maps_paint_each_curve_with_its_own_label_in_a_joined_stroke():
    curves = square_sides()[:2] + [
        Curve(square_sides()[2].points, 1),
        Curve(square_sides()[3].points, 1),
    ]
    for k in range(20):
        strokes, labels, maps = people_strokes(curves, CAMERA, np.random.default_rng(k), 1)
        on = maps.stroke_mask > 0
        assert set(np.unique(maps.curve_label[on])) <= {0.0, 1.0}
        assert np.all(maps.curve_label[~on] == 0)
    assert len(strokes) == len(labels)


def test_a_loop_is_drawn_open_in_two_arcs_or_whole():
    t = np.linspace(0, 2 * np.pi, 96, endpoint=False)
    circle = Curve(np.stack([30 * np.cos(t), 30 * np.sin(t), 0 * t], axis=1), 0, closed=True)
    counts = [
        len(people_strokes([circle], CAMERA, np.random.default_rng(k), 1)[0]) for k in range(40)
    ]
    assert set(counts) == {1, 2}


def test_each_habit_alone_draws_only_what_it_changes():
    """Chaining alone joins sides and never splits one; splitting alone splits sides and
    never joins two; the others keep a square's four strokes; only the wobble bows a
    stroke away from its side, and only partial ends leave a corner undrawn."""
    assert habits_of("people") == set(HABITS) and habits_of("generator") == set()
    sides = square_sides()
    pixels = [CAMERA.project(c.points)[0] for c in sides]
    corners = np.array([p[0] for p in pixels])
    for habit in HABITS:
        counts, strays, misses = [], [], []
        for k in range(30):
            strokes, *_ = people_strokes(
                sides, CAMERA, np.random.default_rng(k), 3, habits_of(f"people-{habit}")
            )
            counts.append(len(strokes))
            ink = np.concatenate(strokes)
            strays += [min(distances_to(q, p).max() for p in pixels) for q in strokes]
            misses.append(distances_to(corners, ink).max())
        if habit == "chain":
            assert min(counts) < 4 and max(counts) == 4
        elif habit == "split":
            assert min(counts) == 4 and max(counts) > 4
        else:
            assert set(counts) == {4}
        if habit not in ("chain", "partial"):  # (which run along two sides, or past one)
            assert (max(strays) > 3.0) == (habit == "wobble"), (habit, max(strays))
        assert (max(misses) > 3.0) == (habit == "partial"), (habit, max(misses))


def test_an_outline_joined_end_to_start_is_read_back_as_its_sides():
    pixels = [CAMERA.project(c.points)[0] for c in square_sides()]
    strokes = [np.linspace(p[0], p[1], 40) for p in pixels]
    joined = join_end_to_start(strokes, 10.0)
    assert len(joined) == 1
    assert len(segment_strokes(joined)) == 4


def test_joining_stops_at_four_curves_and_at_gaps():
    pts = [np.array([[10.0 * k, 0.0], [10.0 * k + 8, 0.0]]) for k in range(6)]
    assert [len(s) for s in join_end_to_start(pts, 3.0)] == [8, 4]
    assert len(join_end_to_start(pts, 1.0)) == 6
