# SPDX-License-Identifier: LGPL-2.1-or-later
"""Document-level checks run inside `freecadcmd` (see test_document.py).

The check named by SKETCH2CAD_CHECK runs; the exit code is 0 on success, 1 on failure.
"""
import os
import sys
import traceback

sys.path.insert(0, os.environ["SKETCH2CAD_ROOT"])
from Sketch2CADWorkbench.freecad import env  # noqa: E402

env.bootstrap()

import FreeCAD  # noqa: E402
import Part  # noqa: E402,F401

from Sketch2CADWorkbench.brep.exchange import export_step  # noqa: E402
from Sketch2CADWorkbench.brep.operators import build, replay  # noqa: E402
from Sketch2CADWorkbench.brep.protocol import load  # noqa: E402
from Sketch2CADWorkbench.freecad.make.make_model import (  # noqa: E402
    features, make_model_from_protocol, protocol_from_model)
from Sketch2CADWorkbench.freecad.shapes import from_part, to_part  # noqa: E402

EXAMPLES = os.path.join(os.environ["SKETCH2CAD_ROOT"], "examples", "protocols")
TMP = os.environ.get("SKETCH2CAD_TMP", "/tmp")


def close(a, b, rel=1e-6):
    return abs(a - b) <= rel * max(abs(a), abs(b))


def tree_from_protocol():
    for name in ("camera", "mixer", "lamp"):
        p = load(os.path.join(EXAMPLES, f"{name}.json"))
        doc = FreeCAD.newDocument(name)
        model = make_model_from_protocol(doc, p)
        chain = features(model)
        assert len(chain) == len(p.operations) + 1, (name, len(chain))
        vols = [s.Volume() for s in replay(p)]
        got = [o.Shape.Volume for o in chain]
        assert all(close(a, b) for a, b in zip(vols, got)), (name, vols, got)
        assert all(o.isValid() for o in chain), name
        assert protocol_from_model(model) == p, name
        FreeCAD.closeDocument(doc.Name)


def edit_and_recompute():
    p = load(os.path.join(EXAMPLES, "mixer.json"))
    doc = FreeCAD.newDocument("edit")
    model = make_model_from_protocol(doc, p)
    chain = features(model)
    before = [o.Shape.Volume for o in chain]
    column = chain[1]  # the first prism: the mixer's column
    column.Length = 70.0
    doc.recompute()
    after = [o.Shape.Volume for o in chain]
    assert after[0] == before[0]  # steps before the edit are untouched
    assert all(a > b for a, b in zip(after[1:], before[1:])), (before, after)
    edited = protocol_from_model(model)
    assert close(build(edited).Volume(), after[-1])
    sweep = chain[3]  # the bowl: its profile follows a radius change in proportion
    inner = [tuple(v) for v in sweep.ProfileInner]
    sweep.Radius1 = sweep.Radius1.Value * 1.5
    assert [tuple(v) for v in sweep.ProfileInner] != inner
    doc.recompute()
    assert sweep.isValid()


def error_state_keeps_the_rest():
    p = load(os.path.join(EXAMPLES, "camera.json"))
    doc = FreeCAD.newDocument("error")
    model = make_model_from_protocol(doc, p)
    chain = features(model)
    good = chain[2].Shape.Volume
    chain[3].Polygon = chain[3].Polygon[:2]  # 2 vertices: cannot be built
    doc.recompute()
    assert "Invalid" in chain[3].State or "Error" in str(chain[3].State), chain[3].State
    assert chain[2].isValid() and close(chain[2].Shape.Volume, good)
    assert len(chain[3].Polygon) == 2  # the user's value stays for them to fix
    # fixing it recovers everything
    chain[3].Polygon = [FreeCAD.Vector(*v) for v in p.operations[2].polygon]
    doc.recompute()
    assert all(o.isValid() for o in chain), [o.State for o in chain]
    assert close(chain[-1].Shape.Volume, build(p).Volume())


def save_fcstd():
    p = load(os.path.join(EXAMPLES, "bolt.json"))
    doc = FreeCAD.newDocument("saved")
    make_model_from_protocol(doc, p)
    doc.saveAs(os.path.join(TMP, "bolt.FCStd"))


def reopen_fcstd():
    doc = FreeCAD.openDocument(os.path.join(TMP, "bolt.FCStd"))
    from Sketch2CADWorkbench.freecad.make.make_model import find_models
    (model,) = find_models(doc)
    p = load(os.path.join(EXAMPLES, "bolt.json"))
    assert protocol_from_model(model) == p
    for o in features(model):
        o.touch()
    doc.recompute()
    chain = features(model)
    assert all(o.isValid() for o in chain)
    assert close(chain[-1].Shape.Volume, build(p).Volume())


def step_and_brep_agree():
    p = load(os.path.join(EXAMPLES, "nut.json"))
    solid = build(p)
    path = os.path.join(TMP, "nut.step")
    export_step(solid, path)
    shape = Part.read(path)
    assert shape.isValid() and len(shape.Solids) == 1
    assert close(shape.Volume, solid.Volume())
    part = to_part(solid)
    assert part.isValid() and close(part.Volume, solid.Volume(), 1e-9)
    assert close(from_part(part).Volume(), solid.Volume(), 1e-9)
    doc = FreeCAD.newDocument("step")
    model = make_model_from_protocol(doc, p)
    path2 = os.path.join(TMP, "nut_fc.step")
    Part.export([model.Tip], path2)
    assert close(Part.read(path2).Volume, solid.Volume())


CHECKS = {f.__name__: f for f in (tree_from_protocol, edit_and_recompute,
                                  error_state_keeps_the_rest, save_fcstd, reopen_fcstd,
                                  step_and_brep_agree)}

try:
    CHECKS[os.environ["SKETCH2CAD_CHECK"]]()
except Exception:
    traceback.print_exc()
    sys.stdout.flush()
    os._exit(1)
print("CHECK PASSED")
sys.stdout.flush()
os._exit(0)
