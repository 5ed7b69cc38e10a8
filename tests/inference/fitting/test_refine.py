# SPDX-License-Identifier: LGPL-2.1-or-later
"""Joint refinement: a primitive drawn by the hand the data generator models is read
closer with the strokes' ends than by closeness alone, and a prism closer still from its
ends alone."""

import numpy as np
from fit_sketches import hand_drawn

from Sketch2CADWorkbench.inference.fitting.refine import prism_edges, prism_from_ends, refine_prism


def test_a_hand_drawn_prism_is_refined_closer_to_the_one_meant_with_the_strokes_ends():
    rng = np.random.default_rng(0)
    errors = {0.0: [], 3.0: []}
    for _ in range(30):
        base = np.array([[0, 0], [50, 5], [55, 40], [5, 35.0]]) + rng.normal(0, 3, (4, 2))
        step, d = np.array([2.0, -3.0]), 12.0
        strokes = [
            hand_drawn(np.linspace(a, b, 30), rng, 3.6)
            for a, b in zip(*prism_edges(base, d * step), strict=False)
        ]
        for weight, got in errors.items():
            poly, length = refine_prism(base, d, step, strokes, end_weight=weight)
            got.append((np.abs(poly - base).mean(), abs(length - d)))
    alone, with_ends = (np.mean(errors[w], axis=0) for w in (0.0, 3.0))
    # the level-1 hand (3.6 px): corners 2.1 -> 1.6 px off, d 0.66 -> 0.53 mm
    assert np.all(with_ends < 0.9 * alone)


def _prism(rng):
    base = np.array([[0, 0], [50, 5], [55, 40], [5, 35.0]]) + rng.normal(0, 3, (4, 2))
    return base, np.array([2.0, -3.0]), 12.0


def test_exact_strokes_give_the_prism_from_their_ends_from_a_start_some_pixels_off():
    rng = np.random.default_rng(1)
    base, step, d = _prism(rng)
    strokes = [np.linspace(a, b, 20) for a, b in zip(*prism_edges(base, d * step), strict=False)]
    poly, length = prism_from_ends(base + rng.normal(0, 3, base.shape), d + 2, step, strokes)
    assert np.allclose(poly, base, atol=1e-6) and abs(length - d) < 1e-6


def test_a_hand_drawn_prism_is_read_closer_from_its_ends_than_refined():
    rng = np.random.default_rng(0)
    refined, from_ends = [], []
    for _ in range(30):
        base, step, d = _prism(rng)
        strokes = [
            hand_drawn(np.linspace(a, b, 30), rng, 3.6)
            for a, b in zip(*prism_edges(base, d * step), strict=False)
        ]
        poly, length = refine_prism(base, d, step, strokes)
        refined.append((np.abs(poly - base).mean(), abs(length - d)))
        poly, length = prism_from_ends(poly, length, step, strokes)
        from_ends.append((np.abs(poly - base).mean(), abs(length - d)))
    # the level-1 hand (3.6 px): corners 1.45 -> 1.20 px off, d 0.38 -> 0.32 mm
    assert np.all(np.mean(from_ends, axis=0) < 0.9 * np.mean(refined, axis=0))


def test_a_corner_no_stroke_draws_stays_where_it_stood():
    rng = np.random.default_rng(2)
    base, step, d = _prism(rng)
    a, b = prism_edges(base, d * step)
    n = len(base)
    # leave out every edge at corner 2: base and far edges 1-2 and 2-3, the side edge 2
    keep = [i for i in range(3 * n) if i not in (1, 2, n + 1, n + 2, 2 * n + 2)]
    strokes = [np.linspace(a[i], b[i], 20) for i in keep]
    start = base + rng.normal(0, 3, base.shape)
    poly, length = prism_from_ends(start, d, step, strokes)
    assert np.allclose(poly[2], start[2], atol=1e-3)
    assert np.allclose(np.delete(poly, 2, axis=0), np.delete(base, 2, axis=0), atol=1e-3)
    assert abs(length - d) < 1e-3
