# SPDX-License-Identifier: LGPL-2.1-or-later
"""The interpret pipeline end to end, with a stand-in for the networks that knows the answer.

The stand-in returns the ground-truth base face and curve maps in the context view the
pipeline itself frames, so these tests check everything but the networks: framing,
rendering, counting, fitting, the B-rep operation, snapping and the error path.
"""

import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest
from reading_fixtures import TOP, Oracle, drawn_on_top, sketch, view

from Sketch2CADWorkbench.brep.compare import volume_iou
from Sketch2CADWorkbench.brep.operators import apply_operation, make_box
from Sketch2CADWorkbench.brep.protocol import (
    AddSubPrism,
    Box,
    Extrude,
    FaceRef,
    Mode,
    OperatorType,
    Shell,
    Sweep,
)
from Sketch2CADWorkbench.inference import interpret as interpret_module
from Sketch2CADWorkbench.inference import search
from Sketch2CADWorkbench.inference.context import InterpretError
from Sketch2CADWorkbench.inference.fitting.regularize import Regularized
from Sketch2CADWorkbench.inference.interpret import interpret
from Sketch2CADWorkbench.inference.options import InterpretOptions
from Sketch2CADWorkbench.sketch.curves import operation_curves
from Sketch2CADWorkbench.sketch.labels import PROFILE
from Sketch2CADWorkbench.sketch.visible import visible_curves

CLI = [sys.executable, "-m", "Sketch2CADWorkbench.cli"]  # the interpreter pytest runs in


def test_an_extrusion_sketch_becomes_the_extrusion(renderer):
    box = make_box(Box((40, 30, 20)))
    op = Extrude(TOP, 9.0)
    cam = view()
    pts, labels = sketch(box, op, cam)
    oracle = Oracle(box, op, pts, labels, cam, renderer)
    got = interpret(box, [cam.project(p)[0] for p in pts], cam, oracle, renderer)
    assert got.op_type is OperatorType.EXTRUDE
    (fitted,) = got.operations
    assert fitted.d == pytest.approx(9.0, abs=0.5)
    assert got.solid.Volume() == pytest.approx(apply_operation(box, op).Volume(), rel=0.02)
    assert set(got.timings_ms) >= {"render", "networks", "fitting", "brep", "total"}
    # the reading's Boolean, built while reading it, is timed as B-rep, not as fitting
    stages = [got.timings_ms[k] for k in ("render", "networks", "fitting", "brep")]
    assert min(stages) >= 0.0 and got.timings_ms["brep"] > 0.0
    assert sum(stages) <= got.timings_ms["total"] * (1 + 1e-9)


def test_snapping_asks_whether_the_strokes_still_fit_a_feature_moved(renderer, monkeypatch):
    op = AddSubPrism(TOP, ((6, -5, 10), (14, -5, 10), (14, 5, 10), (6, 5, 10)), 6.0, Mode.ADD)
    box, _, ctx, _, face_prob, curve = drawn_on_top(renderer, op)
    reading = search.read_operation(
        box, OperatorType.ADDSUB, face_prob, curve, ctx, InterpretOptions()
    )
    asked = []

    def regularize(solid, op, face, view, step, tol, skip, strokes):
        asked.append(strokes)
        return Regularized(op, ())

    monkeypatch.setattr(interpret_module, "regularize_operation", regularize)
    interpret_module._snapped(box, reading, ctx, view(), InterpretOptions())
    (strokes,) = asked
    assert strokes.fits(reading.op)
    moved = replace(reading.op, polygon=tuple((x - 4, y, z) for x, y, z in reading.op.polygon))
    assert not strokes.fits(moved)
    assert strokes.misfit_px(moved) > strokes.misfit_px(reading.op)


def test_a_meaningless_sketch_is_refused_and_the_solid_kept(renderer):
    box = make_box(Box((40, 30, 20)))
    before = box.Volume()
    op = AddSubPrism(TOP, ((0, 0, 10), (5, 0, 10), (0, 5, 10)), 4.0, Mode.ADD)
    cam = view()
    scribble = [np.array([[400.0, 300.0], [420.0, 310.0], [405.0, 330.0]])]
    oracle = Oracle(box, op, [cam.unproject(scribble[0])], [1], cam, renderer)
    with pytest.raises(InterpretError, match="read as addsub, but"):
        interpret(box, scribble, cam, oracle, renderer)
    assert box.Volume() == before and box.isValid()


def test_interpret_command_rejects_a_broken_session(tmp_path):
    (tmp_path / "s.json").write_text('{"format": "sketch2cad-session", "version": 1}')
    out = subprocess.run(
        [*CLI, "interpret", str(tmp_path / "s.json")], capture_output=True, text=True, timeout=120
    )
    assert out.returncode == 2 and "s.json: session: missing key" in out.stderr


def test_a_low_boss_names_the_hole_that_draws_the_same_lines_unless_the_designer_chose(renderer):
    box = make_box(Box((40, 30, 20)))
    low = AddSubPrism(TOP, ((-6, -5, 10), (2, -5, 10), (2, 3, 10), (-6, 3, 10)), 4.0, Mode.ADD)
    tall = replace(low, d=30.0)  # its top, slid back along the view onto f's plane, leaves f
    cam = view()
    for op, other in ((low, Mode.SUBTRACT), (tall, None)):
        pts, labels = sketch(box, op, cam)
        oracle = Oracle(box, op, pts, labels, cam, renderer)
        strokes = [cam.project(p)[0] for p in pts]
        got = interpret(box, strokes, cam, oracle, renderer, InterpretOptions(regularize=False))
        assert got.operations[0].mode is Mode.ADD and got.other_option is other
    chosen = interpret(
        box, strokes, cam, oracle, renderer, InterpretOptions(regularize=False, option=Mode.ADD)
    )
    assert chosen.other_option is None


def test_the_low_boss_names_its_hole_as_an_alternative_that_builds(renderer):
    box = make_box(Box((40, 30, 20)))
    low = AddSubPrism(TOP, ((-6, -5, 10), (2, -5, 10), (2, 3, 10), (-6, 3, 10)), 4.0, Mode.ADD)
    cam = view()
    pts, labels = sketch(box, low, cam)
    oracle = Oracle(box, low, pts, labels, cam, renderer)
    strokes = [cam.project(p)[0] for p in pts]
    got = interpret(box, strokes, cam, oracle, renderer, InterpretOptions(regularize=False))
    other = got.alternative
    assert other.option is Mode.SUBTRACT and other.operations[0].type is OperatorType.ADDSUB
    assert other.solid.Volume() < box.Volume() < got.solid.Volume()
    assert volume_iou(other.solid, apply_operation(box, other.operations[0])) > 0.999


@pytest.mark.parametrize("drawn_as", [Mode.SUBTRACT, Mode.ADD])
def test_a_shallow_hole_and_the_boss_on_its_rim_are_told_apart_by_the_lines_left_hidden(
    renderer, drawn_as
):
    # drawn with every line, a drilled hole and the boss on its rim draw the same lines and
    # both outlines lie on f, so the +/- rule takes the boss; drawn as the view sees each
    # (the hole's floor only inside its rim, the boss's base only in front), they differ
    box = make_box(Box((40, 30, 20)))
    r, d = 8.0, 2.0
    hole = Sweep(TOP, (-2.0, -1.0, 10.0), r, r, d, ((r, d / 3), (r, 2 * d / 3)), Mode.SUBTRACT)
    cam = view()
    drawn = hole
    if drawn_as is Mode.ADD:  # the boss on the hole's rim (tests/inference/holes.py)
        n, v = np.array([0.0, 0.0, 1.0]), np.asarray(cam.direction, float)
        base = np.array(hole.center) - d * n - v * (d / float(-v @ n))
        drawn = replace(hole, center=tuple(base), mode=Mode.ADD)
    truth = apply_operation(box, drawn)
    seen = visible_curves(
        operation_curves(box, drawn, np.array(cam.direction)), cam, renderer.render(truth, cam)
    )
    pts, labels = [c.points for c in seen], [c.label for c in seen]
    oracle = Oracle(box, drawn, pts, labels, cam, renderer)
    strokes = [cam.project(p)[0] for p in pts]
    got = interpret(box, strokes, cam, oracle, renderer, InterpretOptions(regularize=False))
    assert got.operations[0].mode is drawn_as and volume_iou(got.solid, truth) > 0.95
    assert not got.doubtful  # its seen lines explain the strokes


def test_a_deep_square_hole_drawn_without_its_hidden_lines_is_read_as_that_hole(renderer):
    # seen, a deep hole shows its rim whole and of its side edges and floor only what the
    # opening shows: fewer side edges than sides, the floor in part
    box = make_box(Box((40, 30, 20)))
    hole = AddSubPrism(
        TOP, ((-8, -6, 10), (6, -6, 10), (6, 7, 10), (-8, 7, 10)), 9.0, Mode.SUBTRACT
    )
    cam = view()
    truth = apply_operation(box, hole)
    seen = visible_curves(
        operation_curves(box, hole, np.array(cam.direction)), cam, renderer.render(truth, cam)
    )
    assert sum(c.label == PROFILE for c in seen) < 4  # the drawing this test is about
    pts, labels = [c.points for c in seen], [c.label for c in seen]
    oracle = Oracle(box, hole, pts, labels, cam, renderer)
    strokes = [cam.project(p)[0] for p in pts]
    got = interpret(box, strokes, cam, oracle, renderer, InterpretOptions(regularize=False))
    assert got.operations[0].mode is Mode.SUBTRACT and volume_iou(got.solid, truth) > 0.95
    assert not got.doubtful


def off_centre_boss(renderer):
    """A square boss drawn 0.4 mm off a box's top face's centre, 7.3 mm tall: the box,
    the camera, the strokes and a stand-in for the networks."""
    box = make_box(Box((40, 30, 20)))
    op = AddSubPrism(
        TOP,
        ((-4.6, -5.0, 10.0), (5.4, -5.0, 10.0), (5.4, 5.0, 10.0), (-4.6, 5.0, 10.0)),
        7.3,
        Mode.ADD,
    )
    cam = view()
    pts, labels = sketch(box, op, cam)
    return box, cam, [cam.project(p)[0] for p in pts], Oracle(box, op, pts, labels, cam, renderer)


def test_a_reading_records_its_snaps_and_one_can_be_undone(renderer):
    box, cam, strokes, oracle = off_centre_boss(renderer)
    got = interpret(box, strokes, cam, oracle, renderer, InterpretOptions(snap_step=1.0))
    keys = [s.key for s in got.snaps]
    assert "position" in keys and "d" in keys, [s.describe() for s in got.snaps]
    (snapped,) = got.operations
    assert np.mean(snapped.polygon, axis=0)[:2] == pytest.approx((0, 0), abs=1e-6)
    assert snapped.d == pytest.approx(7.0)
    undone = interpret(
        box,
        strokes,
        cam,
        oracle,
        renderer,
        InterpretOptions(snap_step=1.0, skip_snaps=frozenset({"position"})),
    )
    assert "position" not in [s.key for s in undone.snaps]
    assert np.mean(undone.operations[0].polygon, axis=0)[0] == pytest.approx(0.4, abs=0.3)
    assert undone.operations[0].d == pytest.approx(7.0)


def test_a_reading_whose_snapped_shape_does_not_build_stays_as_drawn_saying_why(
    renderer, monkeypatch
):
    box, cam, strokes, oracle = off_centre_boss(renderer)
    snapped = interpret(box, strokes, cam, oracle, renderer, InterpretOptions(snap_step=1.0))
    assert snapped.snaps and not snapped.unsnapped

    def off_the_face(solid, fitted, face, view, step, tol, skip, fits):  # OCCT refuses it
        lifted = tuple((x, y, z + 5.0) for x, y, z in fitted.polygon)
        return Regularized(replace(fitted, polygon=lifted), snapped.snaps)

    monkeypatch.setattr(interpret_module, "regularize_operation", off_the_face)
    got = interpret(box, strokes, cam, oracle, renderer, InterpretOptions(snap_step=1.0))
    drawn = interpret(box, strokes, cam, oracle, renderer, InterpretOptions(regularize=False))
    assert got.operations == drawn.operations and got.snaps == ()
    assert volume_iou(got.solid, drawn.solid) == pytest.approx(1.0)
    assert got.unsnapped.startswith("snapped, it would not build (")
    assert "off the base face's plane" in got.unsnapped


def test_a_chosen_boolean_reads_a_primitive_however_sure_the_classifier_is_of_another(renderer):
    # examples/sessions/pipe.json step 3: a bore drawn down a post, the classifier sure of
    # an extrusion (p 0.9997, sweep 0.0003); the designer chose subtract, a primitive's
    box = make_box(Box((40, 30, 10)))
    post = apply_operation(
        box,
        Sweep(
            FaceRef((0.0, 0.0, 5.0), (0.0, 0.0, 1.0)),
            (0.0, 0.0, 5.0),
            8.0,
            8.0,
            40.0,
            ((8.0, 40 / 3), (8.0, 80 / 3)),
        ),
    )
    top = FaceRef((0.0, 0.0, 45.0), (0.0, 0.0, 1.0))
    bore = Sweep(
        top, (0.0, 0.0, 45.0), 6.0, 6.0, 40.0, ((6.0, 40 / 3), (6.0, 80 / 3)), Mode.SUBTRACT
    )
    cam = view()
    pts, labels = sketch(post, bore, cam)

    class SaysExtrude(Oracle):
        def classify(self, inputs):
            return np.array([0.9997, 1e-9, 1e-9, 0.0003])

    strokes = [cam.project(p)[0] for p in pts]
    oracle = SaysExtrude(post, bore, pts, labels, cam, renderer)
    got = interpret(
        post,
        strokes,
        cam,
        oracle,
        renderer,
        InterpretOptions(regularize=False, option=Mode.SUBTRACT),
    )
    assert got.op_type is OperatorType.SWEEP
    assert volume_iou(got.solid, apply_operation(post, bore)) > 0.97
    unchosen = interpret(post, strokes, cam, oracle, renderer, InterpretOptions(regularize=False))
    # without a choice the extrusion the classifier favours explains the strokes poorly,
    # so the sweep it all but rules out is read too: its clear fit is the bore
    assert unchosen.op_type is OperatorType.SWEEP
    assert volume_iou(unchosen.solid, apply_operation(post, bore)) > 0.97
    # an extrusion is never read with a Boolean chosen; what no prism or sweep fits is
    # refused, saying why
    op = Extrude(top, -10.0)
    pts, labels = sketch(post, op, cam)
    with pytest.raises(InterpretError, match="with subtract chosen, only prisms and sweeps"):
        interpret(
            post,
            [cam.project(p)[0] for p in pts],
            cam,
            SaysExtrude(post, op, pts, labels, cam, renderer),
            renderer,
            InterpretOptions(regularize=False, option=Mode.SUBTRACT),
        )


class FourClasses(Oracle):
    """A classifier of the paper's four, sure of an extrusion, as a rim often reads."""

    def classify(self, inputs):
        return np.array([0.7, 0.2, 0.06, 0.04])


def read_a_rim(renderer):
    """The interpretation of a shell's rim drawn on the top of a box, read by
    FourClasses (no shell class: the rim proposes the shell)."""
    box, op, cam = make_box(Box((40, 30, 20))), Shell(TOP, 3.0), view()
    pts, labels = sketch(box, op, cam)
    return interpret(
        box,
        [cam.project(p)[0] for p in pts],
        cam,
        FourClasses(box, op, pts, labels, cam, renderer),
        renderer,
        InterpretOptions(regularize=False),
    )


def test_a_shell_proposed_by_its_rim_lists_only_the_classifiers_own_probabilities(renderer):
    """A classifier of the paper's four has no shell class: a rim drawn on the top
    proposes the shell, and the reading lists the four probabilities as the classifier
    gave them, without the shell's stand-in (the likeliest class's)."""
    got = read_a_rim(renderer)
    assert got.op_type is OperatorType.SHELL and got.shell_by_rim
    assert got.classified == pytest.approx(
        {"extrude": 0.7, "bevel": 0.2, "addsub": 0.06, "sweep": 0.04}
    )


def test_a_sketch_nothing_reads_names_the_networks_reading_not_the_shell_its_rim_proposed(
    renderer, monkeypatch
):
    """A rim drawn on the top proposes the shell, tried first; where no operator reads
    the strokes, the reason given is the classifier's likeliest operator's, the shell's
    after it: the networks never read a shell there."""

    def fails(solid, kind, *args):
        raise search.FitError(f"no {kind.value} here")

    monkeypatch.setattr(search, "read_operation", fails)
    with pytest.raises(InterpretError) as refused:
        read_a_rim(renderer)
    assert str(refused.value).startswith("read as extrude, but no extrude here"), refused.value
