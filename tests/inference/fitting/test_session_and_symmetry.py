# SPDX-License-Identifier: LGPL-2.1-or-later
"""Session files round-trip and reject malformed input; symmetry mirrors operations exactly."""
import copy
import json

import numpy as np
import pytest

from Sketch2CADWorkbench.brep.operators import apply_operation, make_box
from Sketch2CADWorkbench.brep.protocol import AddSubPrism, Bevel, Box, FaceRef, Mode, Sweep
from Sketch2CADWorkbench.brep.symmetry import mid_plane, reflect
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

CAM = OrthoCamera((0, 0, 0), (0.5, 0.6, -0.62), (0, 0, 1), 40.0, 400, 300)


def session():
    strokes = [np.array([[10.0, 20.0], [30.5, 40.25], [50, 45]]), np.array([[1, 2], [3, 4.0]])]
    return Session(Box((40, 30, 20)), [
        SketchStep(CAM, strokes),
        SketchStep(CAM, strokes[:1], InterpretOptions(False, Mode.SUBTRACT, "x"))])


def test_session_round_trips_through_a_file(tmp_path):
    s = session()
    s.save(tmp_path / "s.json")
    back = load_session(tmp_path / "s.json")
    assert back.base == s.base
    assert [st.camera for st in back.steps] == [st.camera for st in s.steps]
    assert [st.choices for st in back.steps] == [st.choices for st in s.steps]
    for a, b in zip(back.steps, s.steps):
        assert all(np.allclose(x, y, atol=1e-3) for x, y in zip(a.strokes, b.strokes))


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


@pytest.mark.parametrize("mutate,message", [
    (lambda d: d.update(format="x"), "format: expected 'sketch2cad-session'"),
    (lambda d: d.update(version=2), "version: unsupported"),
    (lambda d: d["steps"][0].update(strokes=[]), r"steps\[0\].strokes: expected a non-empty list"),
    (lambda d: d["steps"][0]["strokes"][0].__setitem__(1, [1]),
     r"steps\[0\].strokes\[0\]\[1\]: expected a list of 2 numbers"),
    (lambda d: d["steps"][0]["strokes"].__setitem__(1, [[1, 2]]),
     r"steps\[0\].strokes\[1\]: expected a list of at least 2 points"),
    (lambda d: d["steps"][1]["camera"].update(width=3.5), r"steps\[1\].camera.width: expected an integer"),
    (lambda d: d["steps"][1]["camera"].update(up=[0.5, 0.6, -0.62]), r"steps\[1\].camera: camera up"),
    (lambda d: d["steps"][1]["camera"].update(scale=-1), r"steps\[1\].camera: camera scale must be positive"),
    (lambda d: d["steps"][1]["choices"].update(symmetry="w"), r"steps\[1\].choices.symmetry: expected null"),
    (lambda d: d["steps"][1]["choices"].update(option="both"), r"steps\[1\].choices.option"),
    (lambda d: d["steps"][1]["choices"].update(regularize="yes"), r"regularize: expected true or false"),
    (lambda d: d["steps"][0].update(extra=1), r"steps\[0\].extra: unknown key"),
])
def test_malformed_session_names_field_and_value(mutate, message):
    d = copy.deepcopy(session().to_dict())
    mutate(d)
    with pytest.raises(SessionError, match=message):
        session_from_dict(json.loads(json.dumps(d)))


def test_unreadable_session_names_the_file(tmp_path):
    (tmp_path / "s.json").write_text("{nope")
    with pytest.raises(SessionError, match="s.json: not valid JSON"):
        load_session(tmp_path / "s.json")


def test_mirrored_prism_lands_on_the_opposite_side_with_equal_volume():
    box = make_box(Box((40, 30, 20)))
    op = AddSubPrism(FaceRef((0, 0, 10), (0, 0, 1)),
                     ((8, 3, 10), (16, 3, 10), (16, 9, 10), (8, 9, 10)), 5.0, Mode.ADD)
    origin, normal = mid_plane(box, "x")
    mirrored = reflect(op, origin, normal)
    assert [p[0] for p in mirrored.polygon] == pytest.approx([-8, -16, -16, -8])
    one = apply_operation(box, op)
    both = apply_operation(one, mirrored)
    assert both.Volume() - one.Volume() == pytest.approx(one.Volume() - box.Volume(), rel=1e-9)
    bb = both.BoundingBox()
    assert (bb.xmin, bb.xmax) == pytest.approx((-20, 20))


def test_mirrored_sweep_on_a_side_face_uses_the_opposite_face():
    box = make_box(Box((40, 30, 20)))
    op = Sweep(FaceRef((20, 0, 0), (1, 0, 0)), (20, 4, 2), 3.0, 3.0, 6.0, ((3, 2), (3, 4)), Mode.ADD)
    mirrored = reflect(op, *mid_plane(box, "x"))
    assert mirrored.face.normal == pytest.approx((-1, 0, 0))
    out = apply_operation(apply_operation(box, op), mirrored)
    assert (out.BoundingBox().xmin, out.BoundingBox().xmax) == pytest.approx((-26, 26))


def test_a_bevel_along_a_whole_edge_the_plane_halves_is_not_mirrored_onto_itself():
    from Sketch2CADWorkbench.inference.interpret import apply_with_symmetry
    box = make_box(Box((40, 30, 20)))
    # the front face's top-right corner rounded through the whole depth (y = -15 to 15)
    op = Bevel(FaceRef((0, -15, 0), (0, -1, 0)), (20, -15, 10), (20, 15, 10),
               ((16, -15, 10), (18.2, -15, 10), (20, -15, 8.2), (20, -15, 6)))
    alone = apply_operation(box, op)
    ops, result = apply_with_symmetry(box, op, "y")
    assert ops == (op,) and result.Volume() == pytest.approx(alone.Volume(), rel=1e-9)
    ops, result = apply_with_symmetry(box, op, "x")  # the other side's edge: mirrored
    assert len(ops) == 2
    assert box.Volume() - result.Volume() == pytest.approx(2 * (box.Volume() - alone.Volume()),
                                                           rel=1e-6)


def test_base_face_is_counted_and_an_unsure_face_map_still_decides():
    from Sketch2CADWorkbench.inference.fitting.base_face import select_base_face
    box = make_box(Box((40, 30, 20)))
    ids = np.zeros((64, 64), np.int32)
    ids[:, 32:] = 5
    ids[:4] = -1
    sure = np.where(ids == 5, 0.9, 0.1)
    assert select_base_face(sure, ids, box).isSame(box.Faces()[5])
    unsure = np.where(ids == 5, 0.4, 0.2)  # nothing passes 0.5: the higher mean wins
    assert select_base_face(unsure, ids, box).isSame(box.Faces()[5])


def test_a_sketch_beside_the_model_is_a_fit_error_not_a_crash():
    from Sketch2CADWorkbench.inference.fitting.base_face import select_base_face
    from Sketch2CADWorkbench.inference.fitting.common import FitError
    box = make_box(Box((40, 30, 20)))
    background = np.full((64, 64), -1, np.int32)
    with pytest.raises(FitError, match="not in view"):
        select_base_face(np.full((64, 64), 0.9), background, box)


def test_base_face_is_planar_even_when_a_curved_face_gets_more_votes():
    from Sketch2CADWorkbench.inference.fitting.base_face import select_base_face
    box = make_box(Box((40, 30, 20)))
    top = FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0))
    post = apply_operation(box, Sweep(top, (0.0, 0.0, 10.0), 5.0, 5.0, 10.0,
                                      ((5.0, 10 / 3), (5.0, 20 / 3)), Mode.ADD))
    faces = post.Faces()
    side = next(i for i, f in enumerate(faces) if f.geomType() == "CYLINDER")
    disk = next(i for i, f in enumerate(faces) if f.geomType() == "PLANE"
                and abs(f.Center().z - 20.0) < 1e-6)
    ids = np.full((64, 64), -1, np.int32)
    ids[:40] = side
    ids[40:50] = disk
    got = select_base_face(np.where(ids >= 0, 0.9, 0.0), ids, post)
    assert got.isSame(faces[disk])
