# SPDX-License-Identifier: LGPL-2.1-or-later
"""Reopening document_checks.py's FCStd in a fresh freecadcmd process."""

import json
import os
import sys

sys.path.insert(0, os.path.join(os.environ["SKETCH2CAD_ROOT"], "tests", "freecad", "scripts"))
import FreeCAD
from harness import EXAMPLES, TMP, check, close, finish, run_checks, tested_checkout

DATA = os.path.join(os.environ["SKETCH2CAD_ROOT"], "tests", "freecad", "data")

from Sketch2CADWorkbench.brep.operators import replay  # noqa: E402
from Sketch2CADWorkbench.brep.protocol import load  # noqa: E402
from Sketch2CADWorkbench.freecad_layer.queries import (  # noqa: E402
    failed_features,
    features,
    find_models,
    protocol_from_model,
)


def reopen_and_recompute(path: str):
    """Open the hammer's FCStd: the same tree and protocol, every step rebuilt as the core
    replays it, and the restored proxies still work. Returns the model's features."""
    p = load(os.path.join(EXAMPLES, "hammer.json"))
    doc = FreeCAD.openDocument(path)
    (model,) = find_models(doc)
    chain = features(model)
    assert [o.Name for o in model.Group] == [o.Name for o in chain]
    assert protocol_from_model(model) == p
    for o in chain:
        o.touch()
    doc.recompute()
    assert not failed_features(model)
    want = [s.Volume() for s in replay(p)]
    assert all(close(o.Shape.Volume, v) for o, v in zip(chain, want, strict=False))
    sweep = next(o for o in chain if o.Proxy.TYPE == "Sketch2CAD::Sweep")
    inner = sweep.Proxy.inner(sweep)
    sweep.Radius0 = sweep.Radius0.Value * 1.2  # the restored proxy still retunes
    assert sweep.Proxy.inner(sweep) != inner
    return chain


@check
def reopen_fcstd():
    tested_checkout()
    with open(os.path.join(TMP, "hammer-volumes.json")) as f:
        saved = json.load(f)
    doc = FreeCAD.openDocument(os.path.join(TMP, "hammer.FCStd"))
    (model,) = find_models(doc)
    assert all(close(o.Shape.Volume, v) for o, v in zip(features(model), saved, strict=False))
    FreeCAD.closeDocument(doc.Name)
    reopen_and_recompute(os.path.join(TMP, "hammer.FCStd"))


@check
def reopen_fcstd_saved_by_other_versions():
    # made by this check list's save_fcstd in FreeCAD 0.20.2 and 1.1.3 (document_checks.py,
    # its TMP/hammer.FCStd); each FreeCAD opens and rebuilds both
    for name in sorted(os.listdir(DATA)):
        if name.endswith(".FCStd"):
            for doc in list(FreeCAD.listDocuments().values()):
                FreeCAD.closeDocument(doc.Name)
            reopen_and_recompute(os.path.join(DATA, name))


@check
def fcstd_saved_by_older_versions_gets_quantity_properties_and_new_names():
    for doc in list(FreeCAD.listDocuments().values()):
        FreeCAD.closeDocument(doc.Name)
    doc = FreeCAD.openDocument(os.path.join(DATA, "hammer-saved-by-0.20.2.FCStd"))
    (model,) = find_models(doc)
    chain = features(model)
    assert [o.Label for o in chain] == [
        "Box",
        "Revolution",
        "Bevel",
        "Pad",
        "Hole",
        "Revolution001",
    ], [o.Label for o in chain]
    prism = chain[4]
    assert "Polygon" not in prism.PropertiesList
    assert [prism.getTypeIdOfProperty(f"Vertex{i}") for i in range(1, 5)] == [
        "App::PropertyPosition"
    ] * 4
    assert prism.getTypeIdOfProperty("FacePoint") == "App::PropertyPosition"
    assert chain[2].getTypeIdOfProperty("ProfileEnd") == "App::PropertyPosition"
    assert chain[1].getTypeIdOfProperty("Control2Height") == "App::PropertyDistance"
    assert prism.Operator == "SubtractPolyhedron" and prism.SketchStep == ""


finish(run_checks())
