# SPDX-License-Identifier: LGPL-2.1-or-later
"""A reading that would not change the model is never offered as the step, a face the
user cannot see from the sketch view comes after the ones they can, and a hole whose face
the networks get wrong is still cut into the face it is drawn on."""

import numpy as np
import pytest
from test_interpret import TOP, Oracle, sketch, view

from Sketch2CADWorkbench.brep.compare import volume_iou
from Sketch2CADWorkbench.brep.faces import resolve_face
from Sketch2CADWorkbench.brep.operators import apply_operation, make_box
from Sketch2CADWorkbench.brep.protocol import AddSubPrism, Box, FaceRef, Mode
from Sketch2CADWorkbench.inference import search
from Sketch2CADWorkbench.inference.context import InterpretError
from Sketch2CADWorkbench.inference.interpret import interpret
from Sketch2CADWorkbench.inference.options import InterpretOptions
from Sketch2CADWorkbench.inference.reading import leaves_unchanged
from Sketch2CADWorkbench.inference.search import hidden_faces
from Sketch2CADWorkbench.render.maps import MapRenderer

BOSS_TOP = FaceRef((-12.5, 0.0, 20.0), (0.0, 0.0, 1.0))
HOLE = AddSubPrism(TOP, ((3, -5, 10), (13, -5, 10), (13, 5, 10), (3, 5, 10)), 4.0, Mode.SUBTRACT)
# the same outline on the block's top plane: it cuts only air
IN_THE_AIR = AddSubPrism(
    BOSS_TOP, ((3, -5, 20), (13, -5, 20), (13, 5, 20), (3, 5, 20)), 4.0, Mode.SUBTRACT
)


@pytest.fixture(scope="module")
def renderer():
    return MapRenderer()


@pytest.fixture(scope="module")
def stepped():
    """A 40 x 30 x 20 box with a 15 mm wide block standing 10 mm on its top's left end."""
    box = make_box(Box((40, 30, 20)))
    block = AddSubPrism(
        TOP, ((-20, -15, 10), (-5, -15, 10), (-5, 15, 10), (-20, 15, 10)), 10.0, Mode.ADD
    )
    return apply_operation(box, block)


def test_a_cut_into_the_air_leaves_the_model_unchanged_and_a_hole_does_not(stepped):
    assert leaves_unchanged(stepped, apply_operation(stepped, IN_THE_AIR))
    assert not leaves_unchanged(stepped, apply_operation(stepped, HOLE))


def test_faces_turned_away_from_the_sketch_view_are_hidden():
    box = make_box(Box((40, 30, 20)))
    d = np.array(view().direction)  # looks down onto the top, the front and the right side
    hidden = hidden_faces(box, view())
    for i, f in enumerate(box.Faces()):
        n = np.array(f.normalAt().toTuple())
        assert (i in hidden) == (n @ d > 0), (i, n)
    assert len(hidden) == 3


class SaysBossTop(Oracle):
    """Perfect curve roles, but F on the block's top: the hole's rim back-projected onto
    that higher plane lies in the air beside the block."""

    def segment(self, inputs, op_type):
        _face, curve = super().segment(inputs, op_type)
        from Sketch2CADWorkbench.inference.context import to_context

        strokes = [self.view.project(p)[0] for p in self.strokes3d]
        ids = to_context(self.solid, strokes, self.view, self.renderer).maps.face_id
        top = resolve_face(self.solid, BOSS_TOP).face
        index = next(i for i, f in enumerate(self.solid.Faces()) if f.isSame(top))
        return (ids == index).astype(np.float32), curve


@pytest.mark.parametrize("option", [None, Mode.SUBTRACT])
def test_a_hole_whose_face_the_networks_get_wrong_is_cut_where_it_is_drawn(
    stepped, renderer, option
):
    cam = view()
    pts, labels = sketch(stepped, HOLE, cam)
    oracle = SaysBossTop(stepped, HOLE, pts, labels, cam, renderer)
    got = interpret(
        stepped,
        [cam.project(p)[0] for p in pts],
        cam,
        oracle,
        renderer,
        InterpretOptions(regularize=False, option=option),
    )
    assert not leaves_unchanged(stepped, got.solid)
    assert volume_iou(got.solid, apply_operation(stepped, HOLE)) > 0.97


def _hole_drawn(stepped, renderer):
    cam = view()
    pts, labels = sketch(stepped, HOLE, cam)
    return [cam.project(p)[0] for p in pts], cam, Oracle(stepped, HOLE, pts, labels, cam, renderer)


def test_a_reading_that_would_change_nothing_is_refused_saying_so(stepped, renderer, monkeypatch):
    strokes, cam, oracle = _hole_drawn(stepped, renderer)
    # every face reads as the cut into the air (as the GUI check saw on a face above)
    monkeypatch.setattr(
        search,
        "fit_on_face",
        lambda solid, kind, index, *a: [(IN_THE_AIR, index, [0] * len(strokes))],
    )
    with pytest.raises(InterpretError, match="would leave the model as it is"):
        interpret(stepped, strokes, cam, oracle, renderer, InterpretOptions(regularize=False))


@pytest.mark.parametrize("option", [None, Mode.SUBTRACT])  # the designer chose subtract
def test_a_reading_that_changes_nothing_is_not_offered_even_when_it_fits_best(
    stepped, renderer, monkeypatch, option
):
    # drawn in the air beside the block, at its top's height; F says the block's top
    cam = view()
    pts, labels = sketch(stepped, IN_THE_AIR, cam)
    strokes = [cam.project(p)[0] for p in pts]
    oracle = SaysBossTop(stepped, IN_THE_AIR, pts, labels, cam, renderer)
    top = resolve_face(stepped, BOSS_TOP).face
    on_top = next(i for i, f in enumerate(stepped.Faces()) if f.isSame(top))
    fit = search.fit_on_face

    def the_air_on_the_blocks_top(solid, kind, index, *a):  # as its own sketch: 0 px off
        return [(IN_THE_AIR, index, labels)] if index == on_top else fit(solid, kind, index, *a)

    monkeypatch.setattr(search, "fit_on_face", the_air_on_the_blocks_top)
    try:
        got = interpret(
            stepped,
            strokes,
            cam,
            oracle,
            renderer,
            InterpretOptions(regularize=False, option=option),
        )
    except InterpretError as e:
        assert "would leave the model as it is" in str(e)
    else:  # another face's reading, which does change the model
        assert abs(got.solid.Volume() - stepped.Volume()) > 0.01 * stepped.Volume()
