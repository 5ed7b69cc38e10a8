# SPDX-License-Identifier: LGPL-2.1-or-later
"""Session files round-trip and reject malformed input, naming the field."""

import copy
import json
import warnings
from pathlib import Path

import numpy as np
import pytest

from Sketch2CADWorkbench.brep.protocol import Box, EdgeSet, Mode
from Sketch2CADWorkbench.inference.options import InterpretOptions
from Sketch2CADWorkbench.inference.session import (
    Session,
    SessionError,
    SketchStep,
    load_session,
    session_from_dict,
    step_from_dict,
    step_to_dict,
)
from Sketch2CADWorkbench.render.camera import OrthoCamera

ROOT = Path(__file__).resolve().parents[2]
CAM = OrthoCamera((0, 0, 0), (0.5, 0.6, -0.62), (0, 0, 1), 40.0, 400, 300)


def session():
    strokes = [np.array([[10.0, 20.0], [30.5, 40.25], [50, 45]]), np.array([[1, 2], [3, 4.0]])]
    return Session(
        Box((40, 30, 20)),
        [
            SketchStep(CAM, strokes),
            SketchStep(CAM, strokes[:1], InterpretOptions(False, Mode.SUBTRACT, "x")),
            SketchStep(
                CAM,
                strokes,
                InterpretOptions(
                    snap_step=0.5, snap_px=8.0, skip_snaps=frozenset({"position", "d"})
                ),
            ),
        ],
    )


def test_session_round_trips_through_a_file(tmp_path):
    s = session()
    s.save(tmp_path / "s.json")
    back = load_session(tmp_path / "s.json")
    assert back.base == s.base
    assert [st.camera for st in back.steps] == [st.camera for st in s.steps]
    assert [st.choices for st in back.steps] == [st.choices for st in s.steps]
    for a, b in zip(back.steps, s.steps, strict=True):
        assert all(np.allclose(x, y, atol=1e-3) for x, y in zip(a.strokes, b.strokes, strict=True))


def test_one_step_round_trips_as_json_and_a_bad_one_names_its_field():
    # a FreeCAD feature keeps the step it was read from this way, to read it again
    step = session().steps[1]
    back = step_from_dict(json.loads(json.dumps(step_to_dict(step))))
    assert (back.camera, back.choices) == (step.camera, step.choices)
    assert np.allclose(back.strokes[0], step.strokes[0], atol=1e-3)
    bad = step_to_dict(step)
    bad["strokes"][0] = [[1, 2]]
    with pytest.raises(SessionError, match=r"step.strokes\[0\]"):
        step_from_dict(bad)


def test_choices_default_to_regularized_and_free():
    d = session().to_dict()
    del d["steps"][0]["choices"]
    assert session_from_dict(d).steps[0].choices == InterpretOptions()


def test_the_snaps_undone_and_the_grid_are_kept_for_the_replay(tmp_path):
    # the Sketch panel's "Undo snap" and the preferences' grid step: a replay that
    # forgot them would snap again what the designer undid
    s = session()
    s.save(tmp_path / "s.json")
    choices = load_session(tmp_path / "s.json").steps[2].choices
    assert (choices.snap_step, choices.snap_px, choices.skip_snaps) == (
        0.5,
        8.0,
        frozenset({"position", "d"}),
    )


def test_a_bevels_edge_set_is_kept_for_the_replay(tmp_path):
    s = session()
    s.steps[2] = SketchStep(CAM, s.steps[2].strokes, InterpretOptions(edges=EdgeSet.OUTLINE))
    s.save(tmp_path / "s.json")
    assert load_session(tmp_path / "s.json").steps[2].choices.edges is EdgeSet.OUTLINE
    assert "edges" not in s.to_dict()["steps"][0]["choices"]  # the default is not written


def test_a_step_with_default_snapping_is_written_as_before_the_snap_choices(tmp_path):
    # older readers (and the example sessions' bytes) see no new keys
    assert set(session().to_dict()["steps"][0]["choices"]) == {"option", "symmetry", "regularize"}


@pytest.mark.parametrize(
    "mutate,message",
    [
        (lambda d: d.update(format="x"), "format: expected 'sketch2cad-session'"),
        (lambda d: d.update(version=2), "version: unsupported"),
        (
            lambda d: d["steps"][0].update(strokes=[]),
            r"steps\[0\].strokes: expected a non-empty list",
        ),
        (
            lambda d: d["steps"][0]["strokes"][0].__setitem__(1, [1]),
            r"steps\[0\].strokes\[0\]\[1\]: expected a list of 2 numbers",
        ),
        (
            lambda d: d["steps"][0]["strokes"].__setitem__(1, [[1, 2]]),
            r"steps\[0\].strokes\[1\]: expected a list of at least 2 points",
        ),
        (
            lambda d: d["steps"][1]["camera"].update(width=3.5),
            r"steps\[1\].camera.width: expected an integer",
        ),
        (
            lambda d: d["steps"][1]["camera"].update(up=[0.5, 0.6, -0.62]),
            r"steps\[1\].camera: camera up",
        ),
        (
            lambda d: d["steps"][1]["camera"].update(scale=-1),
            r"steps\[1\].camera: camera scale must be positive",
        ),
        (
            lambda d: d["steps"][1]["camera"].update(center=[1e300, 1e300, 0]),
            r"steps\[1\].camera.center: expected coordinates within",
        ),
        (
            lambda d: d["steps"][1]["camera"].update(scale=1e200),
            r"steps\[1\].camera.scale: expected from",
        ),
        (
            lambda d: d["steps"][1]["camera"].update(scale=1e-300),
            r"steps\[1\].camera.scale: expected from",
        ),
        (
            lambda d: d["steps"][0]["strokes"][1].__setitem__(0, [1e300, 0]),
            r"steps\[0\].strokes\[1\]: expected pixels within",
        ),
        (
            lambda d: d["steps"][1]["choices"].update(symmetry="w"),
            r"steps\[1\].choices.symmetry: expected null",
        ),
        (lambda d: d["steps"][1]["choices"].update(option="both"), r"steps\[1\].choices.option"),
        (
            lambda d: d["steps"][1]["choices"].update(regularize="yes"),
            r"regularize: expected true or false",
        ),
        (lambda d: d["steps"][0].update(extra=1), r"steps\[0\].extra: unknown key"),
        (lambda d: d["steps"][2]["choices"].update(snap_step=-1), r"steps\[2\].choices.snap_step"),
        (lambda d: d["steps"][2]["choices"].update(snap_px=0), r"steps\[2\].choices.snap_px"),
        (lambda d: d["steps"][2]["choices"].update(snap_px="5"), r"steps\[2\].choices.snap_px"),
        (
            lambda d: d["steps"][2]["choices"].update(skip_snaps=["nope"]),
            r"steps\[2\].choices.skip_snaps: expected a list of snap kinds",
        ),
        (
            lambda d: d["steps"][2]["choices"].update(skip_snaps=[["d"]]),
            r"steps\[2\].choices.skip_snaps",
        ),
        (
            lambda d: d["steps"][2]["choices"].update(edges="rim"),
            r"steps\[2\].choices.edges: expected one of \['drawn', 'chain', 'outline'\]",
        ),
    ],
)
def test_malformed_session_names_field_and_value(mutate, message):
    d = copy.deepcopy(session().to_dict())
    mutate(d)
    with pytest.raises(SessionError, match=message):
        session_from_dict(json.loads(json.dumps(d)))


def test_unreadable_session_names_the_file(tmp_path):
    (tmp_path / "s.json").write_text("{nope")
    with pytest.raises(SessionError, match=r"s.json: not valid JSON"):
        load_session(tmp_path / "s.json")


def test_a_huge_view_direction_is_read_as_its_unit_one_without_numpy_warnings():
    from Sketch2CADWorkbench.brep.operators import make_box
    from Sketch2CADWorkbench.brep.protocol import describe
    from Sketch2CADWorkbench.inference.interpret import interpret
    from Sketch2CADWorkbench.inference.weights import load_predictor
    from Sketch2CADWorkbench.render.maps import MapRenderer

    d = json.loads((ROOT / "examples" / "sessions" / "camera.json").read_text())
    d["steps"] = d["steps"][:1]
    unit = session_from_dict(d)
    d["steps"][0]["camera"]["direction"] = [1e300 * x for x in d["steps"][0]["camera"]["direction"]]
    huge = session_from_dict(d)
    predictor, renderer = load_predictor(), MapRenderer()
    got = []
    for s in (unit, huge):
        with warnings.catch_warnings():
            warnings.simplefilter("error", RuntimeWarning)
            step = s.steps[0]
            got.append(interpret(make_box(s.base), step.strokes, step.camera, predictor, renderer))
    assert [describe(op) for op in got[1].operations] == [describe(op) for op in got[0].operations]
