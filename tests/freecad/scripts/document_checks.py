# SPDX-License-Identifier: LGPL-2.1-or-later
"""Document-level checks, run by test_document.py in one freecadcmd process."""

import json
import os
import sys
import xml.etree.ElementTree as ET
from dataclasses import replace

sys.path.insert(0, os.path.join(os.environ["SKETCH2CAD_ROOT"], "tests", "freecad", "scripts"))
import FreeCAD
import Part
from harness import EXAMPLES, ROOT, TMP, check, close, finish, run_checks, tested_checkout

from Sketch2CADWorkbench.brep.exchange import import_step
from Sketch2CADWorkbench.brep.operators import build, replay
from Sketch2CADWorkbench.brep.protocol import Sweep, load
from Sketch2CADWorkbench.freecad_layer.export import export_step
from Sketch2CADWorkbench.freecad_layer.make.make_model import make_model_from_protocol
from Sketch2CADWorkbench.freecad_layer.queries import failed_features, features, protocol_from_model
from Sketch2CADWorkbench.freecad_layer.shapes import from_part, to_part


def example(name: str):
    return load(os.path.join(EXAMPLES, f"{name}.json"))


def volumes(model) -> list:
    return [o.Shape.Volume for o in features(model)]


def assert_matches_core(model, protocol) -> None:
    """Every step's volume equals the core's replay of `protocol` within 1e-6 relative."""
    want = [s.Volume() for s in replay(protocol)]
    got = volumes(model)
    assert len(got) == len(want) and all(close(a, b) for a, b in zip(got, want, strict=False)), (
        got,
        want,
    )


@check
def startup():
    tested_checkout()
    import cadquery  # noqa: F401
    import freecad
    import numpy

    assert "Sketch2CADWorkbench.freecad_layer.env" in sys.modules, "Init.py did not bootstrap"
    from Sketch2CADWorkbench.freecad_layer import dependencies

    assert numpy.__file__.startswith(dependencies.folder()), (numpy.__file__, dependencies.folder())
    assert all("Sketch2CADWorkbench" not in p for p in freecad.__path__), freecad.__path__


@check
def addon_metadata():
    meta = FreeCAD.Metadata(os.path.join(ROOT, "package.xml"))
    assert (meta.Name, meta.Version) == ("Sketch2CAD", "0.1.0"), (meta.Name, meta.Version)
    assert meta.License[0]["name"] == "LGPL-2.1-or-later", meta.License
    assert any(u["type"] == "repository" and u["branch"] for u in meta.Urls), meta.Urls
    assert meta.supportsCurrentFreeCAD()
    assert os.path.isfile(os.path.join(ROOT, meta.Icon)), meta.Icon
    (wb,) = meta.Content["workbench"]
    assert (wb.Classname, wb.Subdirectory) == ("Sketch2CADWorkbench", "Sketch2CADWorkbench")
    assert os.path.isfile(os.path.join(ROOT, wb.Subdirectory, wb.Icon)), wb.Icon
    with open(os.path.join(ROOT, wb.Subdirectory, "InitGui.py")) as f:
        init_gui = f.read()
    assert f"class {wb.Classname}(Workbench)" in init_gui
    from Sketch2CADWorkbench.freecad_layer.icons import ICONS

    for name in os.listdir(ICONS):
        assert ET.parse(os.path.join(ICONS, name)).getroot().tag.endswith("svg"), name


@check
def tree_from_protocol():
    for name in ("nut", "bolt", "camera", "hammer", "mixer", "lamp"):
        p = example(name)
        doc = FreeCAD.newDocument(name)
        model = make_model_from_protocol(doc, p)
        assert len(features(model)) == len(p.operations) + 1, name
        assert not failed_features(model), name
        assert_matches_core(model, p)
        assert protocol_from_model(model) == p, name
        FreeCAD.closeDocument(doc.Name)


@check
def edit_and_recompute():
    p = example("mixer")
    doc = FreeCAD.newDocument("edit")
    model = make_model_from_protocol(doc, p)
    chain = features(model)
    before = volumes(model)
    chain[1].Length = chain[1].Length.Value + 10.0  # the mixer's column prism
    doc.recompute()
    assert not failed_features(model)
    after = volumes(model)
    assert after[0] == before[0]  # the step before the edit is untouched
    assert all(not close(a, b) for a, b in zip(after[1:], before[1:], strict=False)), (
        before,
        after,
    )
    assert_matches_core(model, protocol_from_model(model))
    # the base box: every step is rebuilt on the wider box
    chain[0].Width = chain[0].Width.Value + 10.0
    doc.recompute()
    assert not failed_features(model)
    assert_matches_core(model, protocol_from_model(model))
    assert all(not close(a, b) for a, b in zip(volumes(model), after, strict=False)), (
        after,
        volumes(model),
    )


@check
def bevel_follows_an_edit_of_an_earlier_extrude():
    # a longer Extrude under a Bevel used to leave the round as a groove below
    # the new top, every feature saying Valid; the bevel now moves to the new corner
    from Sketch2CADWorkbench.brep.operators import locate_bevel
    from Sketch2CADWorkbench.brep.protocol import Bevel, Box, Extrude, FaceRef, Protocol

    top = FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0))
    front = FaceRef((0.0, -15.0, 0.0), (0.0, -1.0, 0.0))
    bevel = Bevel(
        front,
        (20.0, -15.0, 19.535),
        (20.0, 15.0, 19.535),
        (
            (20.0, -15.0, 14.535),
            (20.0, -15.0, 17.285),
            (17.25, -15.0, 19.535),
            (15.0, -15.0, 19.535),
        ),
    )
    p = Protocol(Box((40.0, 30.0, 20.0)), (Extrude(top, 9.535), bevel))
    doc = FreeCAD.newDocument("follow")
    model = make_model_from_protocol(doc, p)
    _box, extrude, bev = features(model)
    removed = extrude.Shape.Volume - bev.Shape.Volume
    extrude.Offset = 15.0
    doc.recompute()
    assert not failed_features(model), [o.State for o in features(model)]
    assert close(extrude.Shape.Volume - bev.Shape.Volume, removed), (
        removed,
        extrude.Shape.Volume - bev.Shape.Volume,
    )
    assert close(bev.Shape.BoundBox.ZMax, 25.0), bev.Shape.BoundBox
    at = locate_bevel(from_part(extrude.Shape), bev.Proxy.operation(bev))
    assert close(at.corner[2], 25.0) and close(at.profile[3][2], 25.0), at
    assert not bev.Shape.isInside(FreeCAD.Vector(19.9, 0.0, 24.9), 1e-6, True)  # rounded off
    assert bev.Shape.isInside(FreeCAD.Vector(19.9, 0.0, 19.0), 1e-6, True)  # no groove
    assert_matches_core(model, protocol_from_model(model))
    FreeCAD.closeDocument(doc.Name)


@check
def a_round_is_a_fillet_or_chamfer_whose_values_edit_and_rebuild_later_steps():
    # the knob: a filleted rim, a bore with a chamfered mouth, a chamfered plate outline
    doc = FreeCAD.newDocument("knob")
    p = example("knob")
    model = make_model_from_protocol(doc, p)
    _box, _knob, fillet, *_, chamfer = features(model)
    assert (fillet.Label, chamfer.Label) == ("Fillet", "Chamfer001"), (fillet.Label, chamfer.Label)
    assert (fillet.Rounding, fillet.Edges, fillet.AcrossEdge) == ("Fillet", "drawn", True)
    assert chamfer.Edges == "outline" and close(chamfer.Distance1.Value, 2.0)
    assert_matches_core(model, p)
    fillet.Radius = 5.0  # the later chamfer rebuilds on the new rim
    doc.recompute()
    assert not failed_features(model), [o.State for o in features(model)]
    assert_matches_core(model, protocol_from_model(model))
    assert protocol_from_model(model).operations[1].radius == 5.0
    fillet.Rounding = "Chamfer"  # renamed, a chamfer of its distances
    fillet.Distance1, fillet.Distance2 = 2.0, 3.0
    doc.recompute()
    assert fillet.Label.startswith("Chamfer"), fillet.Label
    assert protocol_from_model(model).operations[1].distances == (2.0, 3.0)
    fillet.Rounding = "Fillet"
    fillet.Radius = 40.0  # too large for the knob: that feature and the later in error
    doc.recompute()
    assert fillet in failed_features(model) and chamfer in failed_features(model)
    FreeCAD.closeDocument(doc.Name)


@check
def values_follow_an_edit_of_an_earlier_step():
    """A boss on a pad's top, the pad raised: the boss stands on the new top, and its
    properties (face point, vertices) say so, with how far it moved since it was drawn."""
    from Sketch2CADWorkbench.brep.protocol import AddSubPrism, Box, Extrude, FaceRef, Mode, Protocol

    square = tuple((x, y, 20.0) for x, y in ((-5, -5), (5, -5), (5, 5), (-5, 5)))
    boss = AddSubPrism(FaceRef((0.0, 0.0, 20.0), (0.0, 0.0, 1.0)), square, 5.0, Mode.ADD)
    pad = Extrude(FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0)), 10.0)
    doc = FreeCAD.newDocument("values")
    model = make_model_from_protocol(doc, Protocol(Box((40.0, 30.0, 20.0)), (pad, boss)))
    _, extrude, prism = features(model)
    assert (prism.FacePoint.z, prism.Vertex1.z, prism.SketchOffset.Length) == (20.0, 20.0, 0.0)
    extrude.Offset = 15.0
    doc.recompute()
    assert not failed_features(model)
    assert close(prism.Shape.BoundBox.ZMax, 30.0), prism.Shape.BoundBox
    got = (prism.FacePoint.z, prism.Vertex1.z, tuple(prism.SketchOffset))
    assert got == (25.0, 25.0, (0.0, 0.0, 5.0)), got
    assert_matches_core(model, protocol_from_model(model))
    doc.recompute()  # nothing moves on a second recompute
    assert tuple(prism.SketchOffset) == (0.0, 0.0, 5.0)
    FreeCAD.closeDocument(doc.Name)


@check
def a_drilled_cylinder_is_a_hole_and_a_bevel_reads_with_its_size():
    from Sketch2CADWorkbench.brep.protocol import (
        Bevel,
        Box,
        FaceRef,
        Mode,
        Protocol,
        straight_profile,
    )
    from Sketch2CADWorkbench.freecad_layer.objects.bevel import BevelFeature

    front = FaceRef((0.0, -15.0, 0.0), (0.0, -1.0, 0.0))
    drill = Sweep(
        front, (0.0, -15.0, 0.0), 4.0, 4.0, 8.0, straight_profile(4.0, 4.0, 8.0), Mode.SUBTRACT
    )
    doc = FreeCAD.newDocument("hole")
    model = make_model_from_protocol(doc, Protocol(Box((40.0, 30.0, 20.0)), (drill,)))
    hole = features(model)[-1]
    assert hole.Label == "Hole", hole.Label
    hole.Radius1 = 6.0  # a cone: no longer a drilled hole
    doc.recompute()
    assert hole.Label == "Groove", hole.Label
    FreeCAD.closeDocument(doc.Name)
    bevel = Bevel(
        front,
        (20.0, -15.0, 10.0),
        (20.0, 15.0, 10.0),
        ((20.0, -15.0, 5.0), (20.0, -15.0, 7.75), (17.25, -15.0, 10.0), (15.0, -15.0, 10.0)),
    )
    text = BevelFeature.reading(bevel)
    assert text.startswith("Bevel: 5.00 mm,") and "30.00 mm edge" in text, text


@check
def sweep_profile_follows_its_radii():
    doc = FreeCAD.newDocument("retune")
    model = make_model_from_protocol(doc, example("mixer"))
    sweep = next(o for o in features(model) if o.Proxy.TYPE == "Sketch2CAD::Sweep")
    op = sweep.Proxy.operation(sweep)
    sweep.Radius1 = op.r1 * 1.5
    want = op.retuned(r1=op.r1 * 1.5)
    got = sweep.Proxy.operation(sweep)
    assert isinstance(got, Sweep) and all(
        close(a, b, 1e-9) for a, b in zip(sum(got.profile, ()), sum(want.profile, ()), strict=False)
    ), got
    doc.recompute()
    assert not failed_features(model)
    assert_matches_core(model, protocol_from_model(model))


@check
def unbuildable_value_puts_only_that_feature_in_error():
    p = example("camera")
    doc = FreeCAD.newDocument("error")
    model = make_model_from_protocol(doc, p)
    chain = features(model)
    before = volumes(model)
    later = [o.Proxy.operation(o) for o in chain[4:]]
    prism = chain[3]
    prism.Proxy.set_polygon(prism, prism.Proxy.polygon(prism)[:2])  # 2 vertices: no prism
    doc.recompute()
    # the later steps go into error too, rather than keep their solids from before
    assert failed_features(model) == chain[3:], [o.State for o in chain]
    assert "Invalid" in prism.State, prism.State
    assert "3 to 6 vertices" in prism.getStatusString(), prism.getStatusString()
    assert all(
        f"its Base {chain[i - 1].Label} failed to build" in chain[i].getStatusString()
        for i in range(4, len(chain))
    ), [o.getStatusString() for o in chain]
    assert len(prism.Proxy.polygon(prism)) == 2  # the user's value stays, for them to fix
    assert all(close(a, b) for a, b in zip(volumes(model)[:3], before[:3], strict=False))
    assert [o.Proxy.operation(o) for o in chain[4:]] == later  # nothing after it is lost
    # export and save refuse, naming the broken step; the files are not touched
    # (Save protocol runs the same refuse_failed_steps first: commands/protocol.py)
    from Sketch2CADWorkbench.freecad_layer.queries import refuse_failed_steps

    step = os.path.join(TMP, "error.step")
    for attempt in (
        lambda: export_step(model, step),
        lambda: refuse_failed_steps(model, "saving the protocol"),
    ):
        try:
            attempt()
            raise AssertionError("went on with a failed step")
        except ValueError as e:
            assert f"step {prism.Label} failed to build" in str(e), e
    assert not os.path.exists(step)
    prism.FaceNormal = FreeCAD.Vector(0, 0, 0)
    doc.recompute()
    assert "zero vector" in prism.getStatusString(), prism.getStatusString()
    prism.Proxy.set_polygon(prism, p.operations[2].polygon)
    prism.FaceNormal = FreeCAD.Vector(*p.operations[2].face.normal)
    doc.recompute()
    assert not failed_features(model)
    assert_matches_core(model, p)


@check
def save_fcstd():
    # hammer.json uses all four operators
    doc = FreeCAD.newDocument("saved")
    model = make_model_from_protocol(doc, example("hammer"))
    kinds = {o.Proxy.TYPE for o in features(model)}
    assert len(kinds) == 5, kinds  # the box and the four operators
    doc.saveAs(os.path.join(TMP, "hammer.FCStd"))
    with open(os.path.join(TMP, "hammer-volumes.json"), "w") as f:
        json.dump(volumes(model), f)


@check
def interpret_session_inside_freecad():
    # the whole pipeline in FreeCAD's process: torch, the weights, VTK, the fitting
    from Sketch2CADWorkbench.brep.compare import volume_iou
    from Sketch2CADWorkbench.brep.operators import make_box
    from Sketch2CADWorkbench.brep.protocol import Protocol
    from Sketch2CADWorkbench.inference.interpret import interpret
    from Sketch2CADWorkbench.inference.session import load_session
    from Sketch2CADWorkbench.inference.weights import load_predictor
    from Sketch2CADWorkbench.render.maps import MapRenderer

    session = load_session(os.path.join(ROOT, "examples", "sessions", "camera.json"))
    predictor, renderer = load_predictor(), MapRenderer()
    protocol, solid = Protocol(session.base), make_box(session.base)
    for step in session.steps:
        got = interpret(solid, step.strokes, step.camera, predictor, renderer, step.choices)
        for op in got.operations:
            protocol = protocol.append(op)
        solid = got.solid
    assert volume_iou(solid, build(example("camera"))) >= 0.9
    model = make_model_from_protocol(FreeCAD.newDocument("interpreted"), protocol)
    assert not failed_features(model)
    assert close(features(model)[-1].Shape.Volume, solid.Volume())


@check
def step_export_and_brep_transfer():
    p = example("nut")
    solid = build(p)
    part = to_part(solid)
    assert part.isValid() and close(part.Volume, solid.Volume(), 1e-9)
    assert close(from_part(part).Volume(), solid.Volume(), 1e-9)
    doc = FreeCAD.newDocument("step")
    model = make_model_from_protocol(doc, p)
    path = os.path.join(TMP, "nut.step")
    export_step(model, path)
    with open(path) as f:
        assert "10303 214" in f.read(4000), "not AP214"
    read = Part.read(path)
    assert read.isValid() and len(read.Solids) == 1
    assert close(read.Volume, solid.Volume()) and close(import_step(path).Volume(), solid.Volume())
    features(model)[-1].FaceNormal = FreeCAD.Vector(0, 0, 0)  # a failing last step: no
    # export, the file is kept
    doc.recompute()
    size = os.path.getsize(path)
    try:
        export_step(model, path)
        raise AssertionError("exported a model whose last step failed")
    except ValueError as e:
        assert "step Bevel001 failed to build" in str(e), e
    assert os.path.getsize(path) == size


@check
def features_are_named_as_freecad_users_read_them():
    doc = FreeCAD.newDocument("names")
    model = make_model_from_protocol(doc, example("hammer"))
    chain = features(model)
    assert [o.Label for o in chain] == [
        "Box",
        "Revolution",
        "Bevel",
        "Pad",
        "Hole",
        "Revolution001",
    ], [o.Label for o in chain]
    assert [o.Operator for o in chain[1:]] == [
        "AddSweepShape",
        "Bevel",
        "Extrude",
        "SubtractPolyhedron",
        "AddSweepShape",
    ]
    assert all(o.getEditorMode("Operator") == ["ReadOnly"] for o in chain[1:])
    pad, hole = chain[3], chain[4]
    pad.Offset = -2.0  # the sign of the offset makes it a pocket
    hole.Mode = "add"  # the Boolean makes it a boss
    assert (pad.Label, pad.Operator, hole.Label, hole.Operator) == (
        "Pocket",
        "Extrude",
        "Boss",
        "AddPolyhedron",
    ), (pad.Label, hole.Label, hole.Operator)
    hole.Label = "Handle slot"  # the user's name stays when the Boolean flips back
    hole.Mode = "subtract"
    assert (hole.Label, hole.Operator) == ("Handle slot", "SubtractPolyhedron")
    assert hole.Proxy.kind(hole) == "Hole"
    doc.recompute()
    assert not failed_features(model)


LENGTHS = {"App::PropertyLength", "App::PropertyDistance", "App::PropertyPosition"}


@check
def parameters_are_quantities_in_the_users_units():
    from Sketch2CADWorkbench.freecad_layer.make.make_model import FEATURE_OF_OPERATION

    doc = FreeCAD.newDocument("units")
    model = make_model_from_protocol(doc, example("hammer"))
    for o in features(model):
        own = [
            n
            for n in o.PropertiesList
            if o.getGroupOfProperty(n) not in ("Base", "Sketch", "")
            and n not in ("Placement", "Shape", "Label", "Label2")
        ]
        unitless = [n for n in own if o.getTypeIdOfProperty(n) not in LENGTHS]
        # a normal has no unit; the Boolean, the kind of surface, and a bevel's rounding,
        # edge set and form (across an edge or along a crease) are choices
        choices = {"FaceNormal", "FaceSurface", "Mode", "Rounding", "Edges", "AcrossEdge"}
        assert set(unitless) <= choices, (o.Label, unitless)
    schema = FreeCAD.Units.getSchema()
    try:
        FreeCAD.Units.setSchema(3)  # Imperial decimal (in/lb)
        for op in example("hammer").operations:
            text = FEATURE_OF_OPERATION[op.type].reading(op)
            assert " in" in text and " mm" not in text and "f[n=" not in text, text
        pad = FEATURE_OF_OPERATION[example("hammer").operations[2].type].reading(
            example("hammer").operations[2]
        )
        assert pad.startswith("Pad: the face moved out by 0.20 in"), pad
    finally:
        FreeCAD.Units.setSchema(schema)


@check
def the_length_grid_follows_the_unit_schema():
    """Lengths snap by default to a whole unit of the user's schema: 1 mm, 0.5 mm where the
    view shows strokes that precise (zoomed in), 0.05 in in an inch schema; a step chosen
    in the preferences (0: none) wins."""
    from Sketch2CADWorkbench.freecad_layer.preferences import parameters, snap_step
    from Sketch2CADWorkbench.freecad_layer.units import length_grid

    schema = FreeCAD.Units.getSchema()
    try:
        FreeCAD.Units.setSchema(0)  # Standard (mm, kg, s, degree)
        assert (length_grid(0.1), length_grid(0.02)) == (1.0, 0.5)
        FreeCAD.Units.setSchema(3)  # Imperial decimal (in/lb)
        assert length_grid(0.1) == 1.27
    finally:
        FreeCAD.Units.setSchema(schema)
    p = parameters()
    try:
        p.RemFloat("SnapStep")
        assert snap_step(0.1) == length_grid(0.1)
        for chosen in (0.0, 2.0):
            p.SetFloat("SnapStep", chosen)
            assert snap_step(0.1) == chosen
    finally:
        p.RemFloat("SnapStep")


@check
def step_part_is_named_after_the_model():
    import Import

    doc = FreeCAD.newDocument("named")
    model = make_model_from_protocol(doc, example("nut"), label="Hex nut")
    path = os.path.join(TMP, "hex-nut.step")
    export_step(model, path)
    assert FreeCAD.ActiveDocument == doc
    assert "Sketch2CADExport" not in FreeCAD.listDocuments()
    reread = FreeCAD.newDocument("reread")
    Import.insert(path, reread.Name)
    assert [o.Label for o in reread.Objects] == ["Hex nut"], [o.Label for o in reread.Objects]


@check
def a_step_read_again_replaces_its_feature_in_place():
    """What OK does after a step's panel was re-opened (make_model.replace_operation): the
    same operator changes the feature's values; another operator puts a new feature in
    its place, the later steps rebased on it."""
    from Sketch2CADWorkbench.brep.protocol import Extrude
    from Sketch2CADWorkbench.freecad_layer.make.make_model import replace_operation

    p = example("mixer")
    doc = FreeCAD.newDocument("replace")
    model = make_model_from_protocol(doc, p)
    chain = features(model)
    boss = chain[1]
    taller = replace(p.operations[0], d=p.operations[0].d + 5)
    assert replace_operation(boss, taller, sketch="{}") == boss
    assert (boss.Length.Value, boss.SketchStep) == (taller.d, "{}")
    pad, name = Extrude(p.operations[0].face, 60.0), boss.Name
    new = replace_operation(boss, pad)
    doc.recompute()
    assert name not in [o.Name for o in doc.Objects]
    assert (new.Label, new.Base, chain[2].Base) == ("Pad", chain[0], new)
    assert [o.Name for o in model.Group] == [o.Name for o in features(model)]
    assert features(model)[1] == new and model.Tip == chain[-1]
    ops = protocol_from_model(model).operations
    # the later steps keep their kinds, their values moved to where they stand on the pad
    assert ops[0] == pad and [type(o) for o in ops[1:]] == [type(o) for o in p.operations[1:]]
    assert_matches_core(model, protocol_from_model(model))


@check
def steps_on_curved_faces_expose_their_parameters_follow_edits_and_export():
    p = example("pipe")  # a pipe with a radial branch, a pad and a slot on its side
    doc = FreeCAD.newDocument("pipe")
    model = make_model_from_protocol(doc, p)
    chain = features(model)
    assert not failed_features(model) and protocol_from_model(model) == p
    assert_matches_core(model, p)
    branch = chain[4]
    assert (branch.FaceSurface, branch.Label) == ("cylinder", "Revolution001"), (
        branch.FaceSurface,
        branch.Label,
    )
    assert chain[2].FaceSurface == "cylinder" and chain[2].Label == "Pad"
    # a wider pipe: the steps on its side move out with it; a longer branch
    for name in ("Radius0", "Radius1"):
        setattr(chain[1], name, 13.0)
    branch.Offset = 30.0
    doc.recompute()
    assert not failed_features(model), [o.Label for o in failed_features(model)]
    edited = protocol_from_model(model)
    assert edited.operations[3].d == 30.0
    assert_matches_core(model, edited)
    # the branch's end and the pad's top stand out from the wider wall (r 13 + 1 mm)
    assert close(model.Tip.Shape.BoundBox.XMax, 14.0 + 30.0), model.Tip.Shape.BoundBox
    assert any(
        close(f.CenterOfMass.y, -14.0 - 3.0) and f.normalAt(0, 0).y < -0.999
        for f in chain[6].Shape.Faces
    ), "the pad's top did not move out"
    path = os.path.join(TMP, "pipe.step")
    export_step(model, path)
    read = Part.read(path)
    assert read.isValid() and len(read.Solids) == 1
    assert close(read.Volume, build(edited).Volume())
    FreeCAD.closeDocument(doc.Name)


@check
def a_shell_is_a_thickness_whose_value_rebuilds_later_steps():
    p = example("enclosure")
    doc = FreeCAD.newDocument("enclosure")
    model = make_model_from_protocol(doc, p)
    chain = features(model)
    shell = chain[2]
    assert shell.Label == "Thickness" and shell.Proxy.TYPE == "Sketch2CAD::Shell", shell.Label
    assert shell.getTypeIdOfProperty("Thickness") == "App::PropertyLength"
    assert_matches_core(model, p)
    shell.Thickness = 3.0
    doc.recompute()
    thicker = replace(p.operations[1], t=3.0)
    edited = replace(p, operations=(p.operations[0], thicker, *p.operations[2:]))
    assert not failed_features(model)
    assert_matches_core(model, edited)  # the later steps were rebuilt on the thicker walls
    now = protocol_from_model(model)
    assert now.operations[1] == thicker
    # the bosses on the floor followed it up by the extra millimetre
    assert [op.face.point[2] for op in now.operations[3:]] == [-12.0, -12.0], now.listing()
    shell.Thickness = 40.0  # more than the enclosure allows: only it and later steps fail
    doc.recompute()
    assert failed_features(model) == chain[2:], [o.State for o in chain]
    assert "t = 40 mm cannot be built" in shell.getStatusString(), shell.getStatusString()
    FreeCAD.closeDocument(doc.Name)


finish(run_checks())
