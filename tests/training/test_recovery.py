# SPDX-License-Identifier: LGPL-2.1-or-later
"""End-to-end recovery: the fitting stage alone, fed the ground truth, rebuilds the operation."""
import pytest

from Sketch2CADWorkbench.cli import main
from training.recovery import recovery


@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    out = tmp_path_factory.mktemp("gen")
    assert main(["datagen", "--out", str(out), "--count", "16", "--seed", "5",
                 "--noise-level", "1", "--workers", "1", "--shard-size", "8"]) == 0
    return out


def test_fitting_recovers_the_operation_from_ground_truth_segmentation(generated):
    r = recovery(generated, None, 16, oracle=True)
    got = [v for v in r["per_operator"].values() if v["recovery_n"]]
    assert sum(v["recovery_n"] for v in got) == 16
    recovered = sum(v["recovery_rate"] * v["recovery_n"] for v in got)
    # the paper's fitting is exact up to stroke noise: most level-1 sketches come back
    assert recovered >= 12, r
    assert r["interpret_median_ms"] is None  # no networks ran: nothing end-to-end was timed


def test_recovery_limit_counts_samples(generated):
    r = recovery(generated, None, 5, oracle=True)
    assert sum(v["recovery_n"] for v in r["per_operator"].values()) == 5


def test_the_rate_with_the_one_click_flip_is_at_least_the_strict_rate(generated):
    r = recovery(generated, None, 16, oracle=True)
    for v in r["per_operator"].values():
        if v["recovery_n"]:
            assert v["recovery_rate"] <= v["recovery_rate_with_flip"] <= 1.0
            assert 0.0 <= v["other_option_share"] <= 1.0
    # extrusions and bevels have no Boolean to flip
    for op in ("extrude", "bevel"):
        assert r["per_operator"][op]["other_option_share"] in (0.0, None)
