# SPDX-License-Identifier: LGPL-2.1-or-later
"""The model as a PartDesign Body of native features (freecad_layer/partdesign), in
freecadcmd; then opened, recomputed and edited in a FreeCAD without the workbench."""

import os
import subprocess

import pytest
from freecad_process import ROOT, XVFB, freecad_env, run_script

pytestmark = pytest.mark.freecad

CHECKS = [
    "examples_convert_into_native_features_matching_the_core",
    "sketches_are_fully_constrained_by_the_steps_named_parameters",
    "an_intersection_is_kept_as_a_solid_with_the_reason",
    "rounds_convert_into_native_fillets_chamfers_and_sketches",
    "converted_documents_saved_with_one_edit_per_feature",
]
PLAIN_CHECKS = [
    "the_workbench_is_not_installed",
    "converted_documents_recompute_every_feature",
    "one_dimension_per_feature_changes_the_volume_as_the_core_computes",
]


@pytest.fixture(scope="module")
def conversion_run(tmp_path_factory, run_freecad):
    tmp = tmp_path_factory.mktemp("partdesign")
    return tmp, run_freecad("partdesign_checks.py", tmp, timeout=600)


@pytest.mark.parametrize("name", CHECKS)
def test_partdesign(conversion_run, assert_passed, name):
    assert_passed(conversion_run[1], name)


@pytest.fixture(scope="module")
def plain_run(conversion_run, assert_passed):
    """A FreeCAD with a fresh user folder (FREECAD_USER_HOME): no workbench in its Mod."""
    tmp, first = conversion_run
    assert_passed(first, "converted_documents_saved_with_one_edit_per_feature")
    home = tmp / "fresh-user-home"
    home.mkdir()
    env = dict(freecad_env(tmp), FREECAD_USER_HOME=str(home))
    return run_script("plain_freecad_checks.py", tmp, False, 300, env)


@pytest.mark.parametrize("name", PLAIN_CHECKS)
def test_without_the_workbench(plain_run, assert_passed, name):
    assert_passed(plain_run, name)


def test_convert_command_in_the_gui(tmp_path, run_freecad):
    """Sketch2CAD_ConvertToPartDesign on a model loaded in the GUI (the documentation's
    screenshot script, writing into tmp_path; run_freecad has primed the user config)."""
    env = dict(freecad_env(tmp_path), SKETCH2CAD_SCREENSHOT_DIR=str(tmp_path))
    out = subprocess.run(
        XVFB + ["freecad", str(ROOT / "scripts" / "partdesign_screenshot.py")],
        env=env,
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert "CHECK PASSED convert_command" in out.stdout, (out.stdout + out.stderr)[-6000:]
    assert out.returncode == 0
    assert all(
        os.path.getsize(tmp_path / f"partdesign-{n}.png") > 10000 for n in ("tree", "sketch")
    )


def test_build_fcstd_saves_the_body_through_freecadcmd(tmp_path):
    protocol = ROOT / "examples" / "protocols" / "nut.json"
    env = freecad_env(tmp_path)
    out = subprocess.run(
        [str(ROOT / ".bin" / "sketch2cad"), "build", str(protocol), "--fcstd", "nut.FCStd"],
        env=env,
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert out.returncode == 0, out.stdout + out.stderr
    assert "6 of 6 steps native" in out.stdout, out.stdout
    assert (tmp_path / "nut.FCStd").stat().st_size > 1000
