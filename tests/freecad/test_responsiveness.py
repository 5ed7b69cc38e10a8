# SPDX-License-Identifier: LGPL-2.1-or-later
"""Waiting and mouse capture in FreeCAD's GUI, on a virtual X screen (see
scripts/responsiveness_session.py, which prints the measured figures as FIGURE lines)."""

import pytest
from freecad_process import print_figures

pytestmark = [pytest.mark.freecad, pytest.mark.gui]

CHECKS = [
    "first_activation_imports_no_cadquery_and_starts_the_background_load",
    "the_gui_keeps_running_while_the_networks_load",
    "the_sketch_panel_says_the_networks_load_and_interpret_waits_for_them",
    "every_mouse_move_of_a_stroke_is_captured_while_the_view_redraws",
]


@pytest.fixture(scope="module")
def gui_run(tmp_path_factory, run_freecad):
    """One FreeCAD GUI process running every check of scripts/responsiveness_session.py."""
    out = run_freecad("responsiveness_session.py", tmp_path_factory.mktemp("waiting"), gui=True)
    print_figures(out)
    return out


@pytest.mark.parametrize("name", CHECKS)
def test_responsiveness(gui_run, assert_passed, name):
    assert_passed(gui_run, name)


def test_every_check_ran(gui_run, assert_all_ran):
    assert_all_ran(gui_run, CHECKS)
