# SPDX-License-Identifier: LGPL-2.1-or-later
"""PartDesign conversion checks, run by test_partdesign.py in one freecadcmd process.

This checkout is imported whatever FreeCAD's Mod folder links to. The converted documents
are saved in SKETCH2CAD_TMP with edits.json: for each feature one dimension to change,
its new value and the volume the core computes after that change, for
plain_freecad_checks.py to check in a FreeCAD without the workbench.
"""

import json
import os
import sys
from dataclasses import replace

ROOT = os.environ["SKETCH2CAD_ROOT"]
sys.path.insert(0, os.path.join(ROOT, "tests", "freecad", "scripts"))
sys.path.insert(0, os.path.join(ROOT, "tests"))
sys.path.insert(0, ROOT)
for _name in [m for m in sys.modules if m.split(".")[0] == "Sketch2CADWorkbench"]:
    del sys.modules[_name]  # the Mod folder's workbench may be another checkout
from Sketch2CADWorkbench.freecad_layer import env  # noqa: E402

env.bootstrap()

import FreeCAD  # noqa: E402
from harness import EXAMPLES, TMP, check, close, finish, run_checks  # noqa: E402
from round_fixtures import round_protocols  # noqa: E402

from Sketch2CADWorkbench.brep.features import plan_protocol  # noqa: E402
from Sketch2CADWorkbench.brep.operators import apply_operation, build, make_box  # noqa: E402
from Sketch2CADWorkbench.brep.protocol import (  # noqa: E402
    AddSubPrism,
    Bevel,
    Extrude,
    Mode,
    Protocol,
    Sweep,
    load,
)
from Sketch2CADWorkbench.freecad_layer.partdesign.convert import (  # noqa: E402
    NOT_NATIVE,
    TOL,
    convert_protocol,
)
from Sketch2CADWorkbench.freecad_layer.shapes import to_part  # noqa: E402

# a prism, bevels, a "replace by" (bolt); Bezier sweeps, a face pad (lamp); steps on a
# cylinder's side: a radial extrusion, a sweep and prisms (pipe)
NAMES = ("bolt", "lamp", "pipe")
CONVERTED = {}  # name -> (document, conversion, the protocol's plan: its core solids)


def example(name: str) -> Protocol:
    return load(os.path.join(EXAMPLES, f"{name}.json"))


def symmetric_difference(shape, core) -> float:
    core = to_part(core)
    return (shape.cut(core).Volume + core.cut(shape).Volume) / core.Volume


@check
def examples_convert_into_native_features_matching_the_core():
    for name in NAMES:
        protocol = example(name)
        doc = FreeCAD.newDocument(name)
        conversion = convert_protocol(doc, protocol, name)
        assert all(s.native for s in conversion.steps), [
            (s.step, s.reason) for s in conversion.steps if not s.native
        ]
        assert [s.step for s in conversion.steps] == list(range(len(protocol.operations) + 1))
        bad = [o.Name for o in doc.Objects if not o.isValid()]
        assert not bad, bad
        body = conversion.body
        plan = plan_protocol(protocol)
        core = plan.solids[-1]
        assert close(body.Shape.Volume, core.Volume(), TOL), (body.Shape.Volume, core.Volume())
        assert symmetric_difference(body.Shape, core) <= TOL
        # only FreeCAD's own types: the file needs no workbench
        assert all(
            o.TypeId.split("::")[0] in ("PartDesign", "Sketcher", "App", "Part")
            for o in doc.Objects
        )
        assert not any("Python" in o.TypeId for o in doc.Objects)
        CONVERTED[name] = (doc, conversion, plan)


@check
def rounds_convert_into_native_fillets_chamfers_and_sketches():
    labels = set()
    for name, protocol in round_protocols().items():
        doc = FreeCAD.newDocument("rounds")
        conversion = convert_protocol(doc, protocol, "rounds")
        assert all(s.native for s in conversion.steps), (name, conversion.steps)
        core = build(protocol)
        assert symmetric_difference(conversion.body.Shape, core) <= TOL, name
        labels |= {s.label for s in conversion.steps}
        for step in conversion.steps:
            obj = doc.getObject(step.feature)
            if step.label in ("Fillet", "Chamfer"):
                assert obj.TypeId == f"PartDesign::{step.label}", (name, obj.TypeId)
            if step.label == "Fillet":  # the step's radius, as the user edits it
                radius = protocol.operations[step.step - 1].radius
                assert close(obj.Radius.Value, radius, 1e-12), name
        FreeCAD.closeDocument(doc.Name)
    assert {"Fillet", "Chamfer", "Bevel"} <= labels, labels


@check
def sketches_are_fully_constrained_by_the_steps_named_parameters():
    for name, (doc, conversion, plan) in CONVERTED.items():
        sketched = [s for s in conversion.steps if s.sketch]
        assert sketched
        for step in sketched:
            sketch = doc.getObject(step.sketch)
            assert sketch.solve() == 0 and sketch.FullyConstrained, (name, sketch.Name)
            named = {c.Name: c.Value for c in sketch.Constraints if c.Name}
            outline = plan.features[step.step].outline  # None: a face's outline, blocked
            want = outline.dims if outline else {}
            assert set(want) <= set(named), (sketch.Name, sorted(want), sorted(named))
            assert all(close(named[k], v) for k, v in want.items()), (named, want)


@check
def an_intersection_is_kept_as_a_solid_with_the_reason():
    protocol = example("mixer")
    top = protocol.operations[0]  # the tall prism on the base's top face
    cut = AddSubPrism(top.face, top.polygon, 30.0, Mode.INTERSECT)
    protocol = Protocol(protocol.base, protocol.operations[:3] + (cut,))
    doc = FreeCAD.newDocument("intersect")
    conversion = convert_protocol(doc, protocol, "Intersect")
    last = conversion.steps[-1]
    assert not last.native and "common" in last.reason, last
    assert all(s.native for s in conversion.steps[:-1])
    base = conversion.body.BaseFeature
    assert base.TypeId == "Part::Feature" and getattr(base, NOT_NATIVE) == last.reason
    assert symmetric_difference(conversion.body.Shape, build(protocol)) <= TOL
    FreeCAD.closeDocument(doc.Name)


def _edit(op, feature):
    """(the changed operation, the feature's dimension to change and its new value)."""
    if isinstance(op, Extrude) and not op.face.surface.curved:
        new = replace(op, d=op.d * 1.05)
        return new, ("property", "Length", abs(new.d))
    if isinstance(op, Extrude):  # a cylinder's side: its offset radius in the sketch
        new = replace(op, d=op.d * 1.5)
        return new, ("constraint", "offset_radius", feature.outline.dims["radius"] + new.d)
    if isinstance(op, AddSubPrism):
        new = replace(op, d=op.d * 1.05)
        return new, ("property", "Length", new.d)
    if isinstance(op, Sweep) and "cp1_r" not in feature.outline.dims:  # a cylinder or cone
        new = op.retuned(d=op.d * 1.05)  # stays straight
        return new, ("constraint", "d", new.d)
    if isinstance(op, Sweep):
        new = replace(op, profile=((op.profile[0][0] * 0.95, op.profile[0][1]), op.profile[1]))
        return new, ("constraint", "cp1_r", new.profile[0][0])
    if isinstance(op, Bevel):
        u, v = feature.outline.point("l_control1").at
        moved = tuple(float(x) for x in feature.frame.to_3d((u * 0.9, v)))
        new = replace(op, profile=(op.profile[0], moved, op.profile[2], op.profile[3]))
        return new, ("constraint", "l_control1_u", u * 0.9)
    raise TypeError(op)


def _entry(path, obj, kind, name, value, measured, volume) -> dict:
    """One edit for plain_freecad_checks.py: set `name` of `obj` (a property, or a named
    sketch constraint) to `value`; `measured`'s volume (a PartDesign feature's solid is
    the Body's after it) must then be `volume`."""
    return {
        "file": path,
        "object": obj.Name,
        "kind": kind,
        "name": name,
        "value": value,
        "measured": measured.Name,
        "volume": volume,
    }


@check
def converted_documents_saved_with_one_edit_per_feature():
    edits = []
    for name, (doc, conversion, plan) in CONVERTED.items():
        protocol = plan.protocol
        path = os.path.join(TMP, f"{name}.FCStd")
        doc.saveAs(path)
        body = conversion.body
        for feature, step in zip(plan.features, conversion.steps, strict=False):
            obj = doc.getObject(step.feature)
            if obj not in body.Group or feature.mode is Mode.REPLACE:
                continue  # a Body before a "replace by" is not the model
            if feature.step == 0:  # the box alone: PartDesign grows it from its corner
                lx, ly, lz = protocol.base.size
                volume = make_box(replace(protocol.base, size=(lx, ly, lz * 1.05))).Volume()
                edits.append(_entry(path, obj, "property", "Height", lz * 1.05, obj, volume))
                continue
            op = protocol.operations[feature.step - 1]
            new, (kind, dim, value) = _edit(op, feature)
            target = doc.getObject(step.sketch) if kind == "constraint" else obj
            # the solid after the edited step, on the unchanged solid before it (later
            # steps follow the edit as far as their attachments do: FreeCAD 1.0 and newer,
            # not 0.20)
            volume = apply_operation(plan.solids[feature.step - 1], new).Volume()
            edits.append(_entry(path, target, kind, dim, value, obj, volume))
        FreeCAD.closeDocument(doc.Name)
    with open(os.path.join(TMP, "edits.json"), "w") as f:
        json.dump(edits, f, indent=1)
    assert len(edits) >= 10, edits


finish(run_checks())
