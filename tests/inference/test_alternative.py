# SPDX-License-Identifier: LGPL-2.1-or-later
"""Which of a reading and its other Boolean the strokes mean (inference/alternative.py)."""

import numpy as np
import pytest

from Sketch2CADWorkbench.inference.alternative import (
    OFFER_PX,
    OUTWEIGH,
    OUTWEIGH_SHARE,
    TIE_PX,
    explained,
    one_way_scores,
    the_meant,
)
from Sketch2CADWorkbench.inference.fitting.verify import SketchFit

ON_F = (1.0, 1.0)  # the base outlines' shares on f of a reading and its other Boolean
LESS_ON_F = (1.0, 0.7)


def test_the_other_boolean_is_taken_only_when_it_explains_the_strokes_clearly_better():
    assert the_meant(5.0, 5.0 - 2 * TIE_PX, ON_F) == (True, True)
    assert the_meant(5.0, 5.0 - TIE_PX / 2, ON_F) == (False, True)  # a tie: the fitted one
    assert the_meant(5.0, 5.0 + TIE_PX / 2, ON_F) == (False, True)


def test_the_other_boolean_standing_off_f_more_than_the_reading_is_not_taken_but_offered():
    assert the_meant(5.0, 5.0 - 2 * TIE_PX, LESS_ON_F) == (False, True)


def test_the_other_boolean_standing_on_f_by_half_is_taken_where_it_outweighs_the_reading():
    assert the_meant(OUTWEIGH * 5.0 + 0.5, 5.0, LESS_ON_F)[0]
    assert not the_meant(OUTWEIGH * 5.0 - 0.5, 5.0, LESS_ON_F)[0]
    mostly_off = (1.0, OUTWEIGH_SHARE - 0.1)  # drawn with every line: the boss slid off f
    assert not the_meant(OUTWEIGH * 5.0 + 0.5, 5.0, mostly_off)[0]


def test_the_one_not_taken_is_offered_only_within_offer_px_of_the_one_taken_or_its_score():
    assert the_meant(2.0, 2.0 + OFFER_PX + 0.5, ON_F) == (False, False)
    assert the_meant(2.0 + OFFER_PX + 0.5, 2.0, ON_F) == (True, False)
    assert the_meant(2.0 + OFFER_PX - 0.5, 2.0, ON_F) == (True, True)
    # a taken reading that explains the strokes poorly leaves room for the other
    assert the_meant(4 * OFFER_PX, 6 * OFFER_PX, ON_F) == (False, True)
    assert the_meant(4 * OFFER_PX, 9 * OFFER_PX, ON_F) == (False, False)


def test_a_reading_is_explained_by_its_lines_drawn_the_way_that_fits_the_strokes_best():
    every = SketchFit(np.full(10, 3.0), np.full(10, 3.0), np.zeros(0))
    seen = SketchFit(np.full(10, 1.0), np.full(10, 2.0), np.zeros(0))
    depth = SketchFit(np.full(10, 1.0), np.full(10, 1.5), np.zeros(0))
    assert explained((every,)) is every
    assert explained((every, seen)) is seen
    assert explained((seen, every)) is seen
    assert explained((every, seen, depth)) is depth


def test_two_readings_are_weighed_with_the_lines_drawn_the_way_that_explains_the_strokes_best():
    def way(px):
        return SketchFit(np.full(10, px), np.full(10, px), np.zeros(0))

    # a seen-drawn hole against the boss on its rim: the boss's every line lies near the
    # strokes too, but the hole's seen lines lie nearest, so both are weighed by those
    hole, boss = (way(1.7), way(0.9)), (way(1.7), way(6.7))
    assert one_way_scores(hole, boss) == pytest.approx((0.9, 6.7))
    assert one_way_scores(boss, hole) == pytest.approx((6.7, 0.9))
    # drawn with every line, both are weighed by every line: a tie
    assert one_way_scores((way(1.2), way(4.0)), (way(1.3), way(5.0))) == pytest.approx((1.2, 1.3))
    # a hole drawn with its depth lines whole: the third way tells it from the boss
    hole, boss = (way(3.0), way(2.5), way(0.8)), (way(3.0), way(2.4), way(4.0))
    assert one_way_scores(hole, boss) == pytest.approx((0.8, 4.0))
