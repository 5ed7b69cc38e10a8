# SPDX-License-Identifier: LGPL-2.1-or-later
"""The extrusion bound: what the strokes' tips tell of d, and how sure the best reading is."""

import numpy as np
import pytest
from steady_hand import TOP, drawn_sample

from Sketch2CADWorkbench.brep.protocol import Extrude
from training.extrusion_bound import bound_of_set, extrusion_bound


def _sample(d_drawn: float, direction, d_true: float = 12.0):
    """An extrusion of the box's top by d_true whose strokes a steady hand drew as d_drawn."""
    return drawn_sample(Extrude(TOP, d_true), Extrude(TOP, d_drawn), direction)


def test_the_oracle_reads_d_from_the_tips_drawn_at_the_moved_corners():
    exact = extrusion_bound(_sample(12.0, (1.0, 0.6, -1.0)))
    assert exact.d_ml == pytest.approx(12.0, abs=1e-6) and exact.ml_recovered
    assert exact.tips >= 4  # every seen moved corner counts
    long = extrusion_bound(_sample(14.0, (1.0, 0.6, -1.0)))  # the hand drew 2 mm more
    assert long.d_ml == pytest.approx(14.0, abs=1e-6)
    assert long.sd == pytest.approx(exact.sd, rel=0.3)  # the same view, as sure


def test_a_view_that_foreshortens_the_extrusion_leaves_the_best_reading_less_sure():
    side = extrusion_bound(_sample(12.0, (1.0, 0.6, -0.3)))
    above = extrusion_bound(_sample(12.0, (0.15, 0.1, -1.0)))  # looking almost along n
    assert above.sd > 2 * side.sd
    assert 0.0 < above.p_best < side.p_best <= 1.0
    assert side.best_recovered


def test_a_set_reports_the_bound_beside_the_oracles_rate(tmp_path):
    from Sketch2CADWorkbench.cli import main

    assert (
        main(
            [
                "datagen",
                "--out",
                str(tmp_path),
                "--count",
                "24",
                "--seed",
                "5",
                "--noise-level",
                "1",
                "--workers",
                "1",
                "--shard-size",
                "8",
            ]
        )
        == 0
    )
    got = bound_of_set(tmp_path)
    assert got["n"] >= 1, got
    for key in ("oracle_ml_rate", "best_decision_rate", "expected_bound"):
        assert 0.0 <= got[key] <= 1.0, got
    assert np.isfinite(got["expected_bound"])
