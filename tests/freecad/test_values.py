# SPDX-License-Identifier: LGPL-2.1-or-later
"""Impossible values typed into the features' properties, in freecadcmd (see
scripts/value_checks.py)."""

import pytest
from freecad_process import print_figures

pytestmark = pytest.mark.freecad

CHECKS = [
    "impossible_values_are_refused_naming_the_property_and_lose_nothing",
    "a_huge_face_normal_is_a_direction_not_a_zero_vector",
]


@pytest.fixture(scope="module")
def values_run(tmp_path_factory, run_freecad):
    """One freecadcmd process running every check of scripts/value_checks.py."""
    out = run_freecad("value_checks.py", tmp_path_factory.mktemp("values"))
    print_figures(out)
    return out


@pytest.mark.parametrize("name", CHECKS)
def test_values(values_run, assert_passed, name):
    assert_passed(values_run, name)


def test_every_check_ran(values_run, assert_all_ran):
    assert_all_ran(values_run, CHECKS)
