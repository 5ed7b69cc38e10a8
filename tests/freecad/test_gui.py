# SPDX-License-Identifier: LGPL-2.1-or-later
"""The workbench in FreeCAD's GUI, on a virtual X screen (see scripts/gui_session.py)."""

import re

import pytest

pytestmark = [pytest.mark.freecad, pytest.mark.gui]

CHECKS = [
    "startup_printed_nothing",
    "workbench_loads_quietly",
    "new_model_is_one_undo_step",
    "view_camera_matches_freecads_projection",
    "strokes_captured_from_mouse_events",
    "sketch_step_adds_one_undoable_feature",
    "sketching_in_a_perspective_view_switches_it_to_orthographic",
    "a_boss_that_draws_like_a_hole_says_so_and_the_boolean_choice_makes_it_one",
    "holes_drawn_with_the_mouse_and_subtract_chosen_are_read_as_those_holes",
    "load_protocol_errors_change_nothing",
    "load_protocol_is_one_undo_step",
    "save_protocol_round_trip",
    "export_step_command",
    "replay_command_rebuilds_step_by_step",
    "loading_and_replaying_a_protocol_show_their_progress",
    "fcstd_reopens_with_view_providers",
    "double_clicking_a_sketched_step_reopens_its_panel_to_edit_it",
    "a_later_step_edited_after_an_earlier_edit_starts_where_it_is_now",
    "a_primitive_read_alone_has_its_other_boolean_one_click_away",
    "sketch_panel_fits_the_default_combo_view",
    "sketch_panel_reads_in_the_users_units_and_names_follow_the_offset",
    "preferences_page_is_shown_and_its_values_are_used",
    "closing_documents_after_sketching_keeps_freecad_running",
]


@pytest.fixture(scope="module")
def gui_run(tmp_path_factory, run_freecad):
    """One FreeCAD GUI process running every check of scripts/gui_session.py."""
    # ten holes drawn and read twice take a minute or two of the budget on a loaded machine
    return run_freecad("gui_session.py", tmp_path_factory.mktemp("gui"), gui=True, timeout=600)


@pytest.mark.parametrize("name", CHECKS)
def test_gui(gui_run, assert_passed, name):
    assert_passed(gui_run, name)


def test_loading_the_workbench_prints_no_error_or_warning(gui_run, assert_passed):
    assert_passed(gui_run, "workbench_loads_quietly")  # which also reads the report view
    text = gui_run.stdout + gui_run.stderr
    loading = text.split("CHECK PASSED workbench_loads_quietly")[0]
    assert not re.search(r"Traceback|Error|Warning|Cannot|failed", loading, re.I), loading[-4000:]


def test_every_check_ran(gui_run, assert_all_ran):
    assert_all_ran(gui_run, CHECKS)
