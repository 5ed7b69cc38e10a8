# SPDX-License-Identifier: LGPL-2.1-or-later
"""The FreeCAD document level, in freecadcmd: the feature tree a CAD user edits."""
import pytest
from conftest_freecad import run_freecadcmd

pytestmark = pytest.mark.freecad


def check(name, tmp_path):
    out = run_freecadcmd("document_checks.py", tmp_path, SKETCH2CAD_CHECK=name)
    assert out.returncode == 0 and "CHECK PASSED" in out.stdout, out.stdout[-3000:] + out.stderr[-3000:]


def test_protocol_loads_into_a_tree_with_the_protocols_volumes(tmp_path):
    check("tree_from_protocol", tmp_path)


def test_editing_a_property_recomputes_that_step_and_the_later_ones(tmp_path):
    check("edit_and_recompute", tmp_path)


def test_unbuildable_value_puts_only_that_feature_in_error(tmp_path):
    check("error_state_keeps_the_rest", tmp_path)


def test_fcstd_reopens_in_a_fresh_freecad_with_the_full_tree(tmp_path):
    check("save_fcstd", tmp_path)
    check("reopen_fcstd", tmp_path)  # a new freecadcmd process


def test_step_export_and_brep_transfer_keep_the_volume(tmp_path):
    check("step_and_brep_agree", tmp_path)
