# SPDX-License-Identifier: LGPL-2.1-or-later
"""STEP files and BREP text carry the solid exactly."""

import pytest

from Sketch2CADWorkbench.brep.exchange import export_step, from_brep_text, import_step, to_brep_text
from Sketch2CADWorkbench.brep.faces import OperationError
from Sketch2CADWorkbench.brep.operators import build
from Sketch2CADWorkbench.brep.protocol import load


@pytest.mark.parametrize("name", ["nut", "camera", "lamp"])
def test_step_reimports_to_a_valid_solid_of_the_same_volume(tmp_path, examples_dir, name):
    solid = build(load(examples_dir / f"{name}.json"))
    export_step(solid, tmp_path / "out.step")
    back = import_step(tmp_path / "out.step")
    assert len(back.Solids()) == 1 and back.isValid()
    assert back.Volume() == pytest.approx(solid.Volume(), rel=1e-6)


def test_step_file_is_ap214(tmp_path, examples_dir):
    export_step(build(load(examples_dir / "nut.json")), tmp_path / "nut.step")
    assert "AUTOMOTIVE_DESIGN" in (tmp_path / "nut.step").read_text()


def test_brep_text_round_trip_keeps_the_solid(examples_dir):
    solid = build(load(examples_dir / "bolt.json"))
    back = from_brep_text(to_brep_text(solid))
    assert back.Volume() == pytest.approx(solid.Volume(), rel=1e-12)
    assert len(back.Faces()) == len(solid.Faces())


def test_unreadable_step_is_an_operation_error(tmp_path):
    (tmp_path / "junk.step").write_text("not a step file")
    with pytest.raises(OperationError, match=r"junk.step"):
        import_step(tmp_path / "junk.step")
    with pytest.raises(OperationError, match="no such STEP file"):
        import_step(tmp_path / "absent.step")
