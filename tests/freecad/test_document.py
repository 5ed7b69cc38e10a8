# SPDX-License-Identifier: LGPL-2.1-or-later
"""The FreeCAD document level, in freecadcmd: the feature tree a CAD user edits."""

import pytest

pytestmark = pytest.mark.freecad

CHECKS = [
    "startup",
    "addon_metadata",
    "tree_from_protocol",
    "edit_and_recompute",
    "bevel_follows_an_edit_of_an_earlier_extrude",
    "a_round_is_a_fillet_or_chamfer_whose_values_edit_and_rebuild_later_steps",
    "values_follow_an_edit_of_an_earlier_step",
    "a_drilled_cylinder_is_a_hole_and_a_bevel_reads_with_its_size",
    "sweep_profile_follows_its_radii",
    "unbuildable_value_puts_only_that_feature_in_error",
    "save_fcstd",
    "interpret_session_inside_freecad",
    "step_export_and_brep_transfer",
    "features_are_named_as_freecad_users_read_them",
    "parameters_are_quantities_in_the_users_units",
    "the_length_grid_follows_the_unit_schema",
    "step_part_is_named_after_the_model",
    "a_step_read_again_replaces_its_feature_in_place",
    "steps_on_curved_faces_expose_their_parameters_follow_edits_and_export",
    "a_shell_is_a_thickness_whose_value_rebuilds_later_steps",
]


@pytest.fixture(scope="module")
def document_run(tmp_path_factory, run_freecad):
    """One freecadcmd process running every check of scripts/document_checks.py."""
    tmp = tmp_path_factory.mktemp("document")
    return tmp, run_freecad("document_checks.py", tmp)


@pytest.mark.parametrize("name", CHECKS)
def test_document(document_run, assert_passed, name):
    assert_passed(document_run[1], name)


@pytest.fixture(scope="module")
def reopen_run(document_run, run_freecad, assert_passed):
    """A fresh freecadcmd reopening what document_run saved (scripts/reopen_checks.py)."""
    tmp, first = document_run
    assert_passed(first, "save_fcstd")
    return run_freecad("reopen_checks.py", tmp)


def test_fcstd_reopens_in_a_fresh_freecad_with_the_full_tree(reopen_run, assert_passed):
    assert_passed(reopen_run, "reopen_fcstd")


def test_fcstd_saved_by_freecad_0_20_and_1_1_opens_and_recomputes(reopen_run, assert_passed):
    assert_passed(reopen_run, "reopen_fcstd_saved_by_other_versions")


def test_fcstd_saved_by_older_versions_gets_quantity_properties_and_new_names(
    reopen_run, assert_passed
):
    assert_passed(
        reopen_run, "fcstd_saved_by_older_versions_gets_quantity_properties_and_new_names"
    )


def test_every_check_ran(document_run, assert_all_ran):
    assert_all_ran(document_run[1], CHECKS)
