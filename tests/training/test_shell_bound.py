# SPDX-License-Identifier: LGPL-2.1-or-later
"""The shell bound: what the rim strokes' tips tell of t, and how sure the best reading is."""

import pytest
from steady_hand import TOP, drawn_sample

from Sketch2CADWorkbench.brep.protocol import Shell
from training.shell_bound import shell_bound


def _sample(t_drawn: float, direction, t_true: float = 4.0, noise_level: int = 1):
    """A shell of the box open at its top, t_true thick, whose rim a steady hand drew as
    for t_drawn."""
    return drawn_sample(Shell(TOP, t_true), Shell(TOP, t_drawn), direction, noise_level)


def test_the_oracle_reads_t_from_the_tips_drawn_at_the_rims_corners():
    exact = shell_bound(_sample(4.0, (1.0, 0.6, -1.0)))
    assert exact.t_ml == pytest.approx(4.0, abs=1e-4) and exact.ml_recovered
    assert exact.tips == 8  # two per corner of the rectangular rim
    thick = shell_bound(_sample(5.0, (1.0, 0.6, -1.0)))  # the hand drew the rim 1 mm in
    assert thick.t_ml == pytest.approx(5.0, abs=1e-4) and not thick.ml_recovered
    assert thick.sd == pytest.approx(exact.sd, rel=1e-3)  # the same view, as sure
    assert exact.fit_recovered and not thick.fit_recovered  # the project's fitting, told f


def test_a_noisier_hand_or_a_grazing_view_leaves_the_best_reading_less_sure():
    steady = shell_bound(_sample(4.0, (1.0, 0.6, -1.0)))
    shaky = shell_bound(_sample(4.0, (1.0, 0.6, -1.0), noise_level=3))
    grazing = shell_bound(_sample(4.0, (1.0, 0.6, -0.2)))  # the top seen nearly edge-on
    assert shaky.sd > 2 * steady.sd and grazing.sd > steady.sd
    assert 0.0 < shaky.p_best < steady.p_best <= 1.0
