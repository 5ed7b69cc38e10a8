# SPDX-License-Identifier: LGPL-2.1-or-later
"""Strokes cut and joined into the curves they draw, as people draw them."""

import itertools
import json
from pathlib import Path

import numpy as np
import pytest

from Sketch2CADWorkbench.brep.geometry import polyline_length
from Sketch2CADWorkbench.sketch.segment import segment_strokes

RNG_SEED = 7


def polyline(points, step: float = 2.0) -> np.ndarray:
    """Points every ~step px along the straight pieces between `points`."""
    p = np.asarray(points, float)
    out = [p[:1]]
    for a, b in itertools.pairwise(p):
        n = max(int(np.ceil(np.linalg.norm(b - a) / step)), 1)
        out.append(a + (b - a) * np.linspace(0, 1, n + 1)[1:, None])
    return np.vstack(out)


def ellipse(t0: float, t1: float, centre=(128, 128), axes=(60, 30), n: int = 120) -> np.ndarray:
    t = np.linspace(t0, t1, n)
    return np.stack([centre[0] + axes[0] * np.cos(t), centre[1] + axes[1] * np.sin(t)], axis=1)


def wobble(p: np.ndarray, amplitude: float) -> np.ndarray:
    """A hand's jitter: small random offsets, lightly smoothed."""
    rng = np.random.default_rng(RNG_SEED)
    d = rng.normal(0, amplitude, p.shape)
    d[1:-1] = (d[:-2] + 2 * d[1:-1] + d[2:]) / 4
    return p + d


def far(p: np.ndarray, q: np.ndarray) -> float:
    """Symmetric Hausdorff distance between two polylines' points."""
    d = np.linalg.norm(p[:, None] - q[None], axis=-1)
    return float(max(d.min(0).max(), d.min(1).max()))


RECT = [(40, 60), (200, 60), (200, 180), (40, 180)]


def test_a_rectangle_in_one_stroke_becomes_its_four_sides():
    stroke = wobble(polyline(RECT + [RECT[0]]), 0.3)
    pieces = segment_strokes([stroke])
    assert len(pieces) == 4
    for a, b in zip(RECT, RECT[1:] + RECT[:1], strict=False):
        side = polyline([a, b])
        assert min(far(side, q) for q in pieces) < 12  # each side is one piece


def test_a_rectangle_started_mid_side_still_becomes_four_sides():
    start = (120, 60)
    stroke = polyline([start] + RECT[1:] + [RECT[0], start])
    assert len(segment_strokes([stroke])) == 4


def test_an_l_and_a_u_shape_are_cut_at_their_corners():
    assert len(segment_strokes([polyline([(40, 40), (40, 200), (180, 200)])])) == 2
    assert len(segment_strokes([polyline([(40, 40), (40, 200), (180, 200), (180, 40)])])) == 3


def test_a_line_in_two_overlapping_strokes_becomes_one():
    a = polyline([(20, 100), (140, 102)])
    b = polyline([(120, 101), (230, 104)])
    pieces = segment_strokes([a, b])
    assert len(pieces) == 1
    assert far(pieces[0], polyline([(20, 100), (230, 104)])) < 4


def test_a_line_in_two_strokes_with_a_gap_becomes_one():
    pieces = segment_strokes(
        [polyline([(20, 100), (120, 100)]), polyline([(128, 100), (230, 101)])]
    )
    assert len(pieces) == 1


def test_a_line_traced_over_becomes_one():
    a = polyline([(20, 100), (230, 100)])
    b = polyline([(40, 102), (200, 101)])
    pieces = segment_strokes([a, b])
    assert len(pieces) == 1 and far(pieces[0], a) < 1


def test_an_ellipse_in_two_arcs_becomes_one_closed_loop():
    pieces = segment_strokes([ellipse(0.05, np.pi + 0.1), ellipse(np.pi + 0.15, 2 * np.pi)])
    assert len(pieces) == 1
    assert np.linalg.norm(pieces[0][0] - pieces[0][-1]) < 2
    assert far(pieces[0], ellipse(0, 2 * np.pi)) < 2


def test_an_ellipse_with_a_tenth_left_open_is_closed():
    pieces = segment_strokes([ellipse(0.0, 0.9 * 2 * np.pi)])
    assert len(pieces) == 1
    assert np.linalg.norm(pieces[0][0] - pieces[0][-1]) < 1e-9


def test_a_smooth_circle_is_not_cut_even_a_small_one():
    big = ellipse(0, 2 * np.pi, axes=(60, 60))
    small = ellipse(0, 2 * np.pi, centre=(30, 30), axes=(5, 5), n=40)
    pieces = segment_strokes([big, small])
    assert len(pieces) == 2
    assert {len(p) for p in pieces} == {len(big), len(small)}


def test_a_long_wobbly_line_is_not_cut_and_comes_back_unchanged():
    t = np.linspace(0, 1, 150)[:, None]
    line = np.hstack([20 + 210 * t, 100 + 4 * np.sin(3 * np.pi * t)])
    stroke = wobble(line, 0.6)
    pieces = segment_strokes([stroke])
    assert len(pieces) == 1 and pieces[0] is stroke


def test_edges_meeting_at_a_corner_stay_apart():
    """Three strokes ending together are a corner of the drawing, even where two of
    them run on in line."""
    strokes = [
        polyline([(20, 100), (120, 100)]),
        polyline([(120, 100), (230, 104)]),
        polyline([(120, 100), (120, 200)]),
    ]
    assert len(segment_strokes(strokes)) == 3


def test_a_short_side_edge_at_a_corner_is_not_swallowed():
    strokes = [polyline([(20, 100), (220, 100)]), polyline([(220, 100), (223, 95)], 1.0)]
    assert len(segment_strokes(strokes)) == 2


@pytest.mark.parametrize("seed", range(5))
def test_order_and_direction_of_strokes_do_not_matter(seed):
    rng = np.random.default_rng(seed)
    strokes = [
        polyline([(20, 20), (140, 22)]),
        polyline([(120, 21), (230, 24)]),
        polyline(RECT + [RECT[0]]),
        ellipse(0.05, np.pi + 0.1, centre=(120, 200), axes=(40, 15)),
        ellipse(np.pi + 0.15, 2 * np.pi, centre=(120, 200), axes=(40, 15)),
    ]
    base = segment_strokes(strokes)
    shuffled = [strokes[i][:: rng.choice([1, -1])] for i in rng.permutation(len(strokes))]
    got = segment_strokes(shuffled)
    assert len(got) == len(base) == 6
    for p in base:
        assert min(far(p, q) for q in got) < 4.0  # cuts fall on a grid along the stroke


def test_a_line_drawn_down_and_back_up_in_one_stroke_ends_where_the_pen_turned():
    # down 40 px along x = 100, then back up past the start: the line runs 60 -> 180
    down, up = polyline([(100, 140), (101, 180)]), polyline([(101, 180), (99, 60)])
    pieces = segment_strokes([wobble(np.vstack([down, up[1:]]), 0.3)])
    assert len(pieces) == 1
    ends = sorted(float(pieces[0][i, 1]) for i in (0, -1))
    assert abs(ends[0] - 60) < 3 and abs(ends[1] - 180) < 3


def test_a_thin_u_is_not_taken_for_a_line_traced_back():
    # two legs 12 px apart (a U-turn of the pen round a slot) are two lines, not one
    u = polyline([(60, 100), (200, 100), (200, 112), (60, 112)])
    pieces = segment_strokes([u])
    assert sum(polyline_length(q) for q in pieces) > 250


def test_a_rim_seen_nearly_edge_on_keeps_its_arcs_whole():
    # the pipe session's second step: rims of a cylinder seen nearly edge-on, each arc
    # run on a little round the ellipse's tip, which no fold of a line is
    session = Path(__file__).resolve().parents[2] / "examples" / "sessions" / "pipe.json"
    strokes = [np.asarray(s, float) for s in json.loads(session.read_text())["steps"][1]["strokes"]]
    pieces = segment_strokes(strokes)
    drawn = sum(polyline_length(s) for s in strokes)
    assert len(pieces) == len(strokes)
    assert sum(polyline_length(q) for q in pieces) >= 0.98 * drawn
