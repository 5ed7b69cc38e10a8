# SPDX-License-Identifier: LGPL-2.1-or-later
"""Run by test_partdesign.py in a FreeCAD whose user folder is fresh (FREECAD_USER_HOME):
no Sketch2CAD in its Mod folder, nothing of it importable. Opens the documents that
partdesign_checks.py converted and saved, recomputes every feature, then makes each
edit of edits.json in turn (one dimension per feature), recomputes, checks that no
object is in error and that the volume is the one the core computed, and undoes it."""

import importlib.util
import json
import os
import sys

sys.path.insert(0, os.path.join(os.environ["SKETCH2CAD_ROOT"], "tests", "freecad", "scripts"))
import FreeCAD
from harness import TMP, check, close, finish, run_checks

with open(os.path.join(TMP, "edits.json")) as _edits:
    EDITS = json.load(_edits)


def errors(doc) -> list:
    return [f"{o.Name}: {o.getStatusString()}" for o in doc.Objects if not o.isValid()]


@check
def the_workbench_is_not_installed():
    mod = os.path.join(FreeCAD.getUserAppDataDir(), "Mod")
    assert not os.path.exists(mod) or not os.listdir(mod), os.listdir(mod)
    assert importlib.util.find_spec("Sketch2CADWorkbench") is None
    assert not [m for m in sys.modules if m.startswith("Sketch2CAD")]


@check
def converted_documents_recompute_every_feature():
    for path in sorted({e["file"] for e in EDITS}):
        doc = FreeCAD.openDocument(path)
        volumes = {o.Name: o.Shape.Volume for o in doc.Objects if o.TypeId == "PartDesign::Body"}
        for obj in doc.Objects:
            obj.touch()
        doc.recompute()
        assert not errors(doc), errors(doc)
        for name, volume in volumes.items():
            assert close(doc.getObject(name).Shape.Volume, volume), name
        FreeCAD.closeDocument(doc.Name)


@check
def one_dimension_per_feature_changes_the_volume_as_the_core_computes():
    docs, done = {}, []
    for edit in EDITS:
        doc = docs.get(edit["file"]) or docs.setdefault(
            edit["file"], FreeCAD.openDocument(edit["file"])
        )
        obj = doc.getObject(edit["object"])
        if edit["kind"] == "property":
            old = getattr(obj, edit["name"])
            setattr(obj, edit["name"], edit["value"])
        else:
            old = obj.getDatum(edit["name"])
            obj.setDatum(edit["name"], FreeCAD.Units.Quantity(edit["value"], FreeCAD.Units.Length))
        doc.recompute()
        assert not errors(doc), (edit, errors(doc))
        got = doc.getObject(edit["measured"]).Shape.Volume
        assert close(got, edit["volume"]), (edit, got)
        if edit["kind"] == "property":
            setattr(obj, edit["name"], old)
        else:
            obj.setDatum(edit["name"], old)
        doc.recompute()
        done.append(f"{os.path.basename(edit['file'])}:{edit['object']}.{edit['name']}")
    print("\nFIGURE edits " + " ".join(done), file=sys.__stdout__)


finish(run_checks())
