# SPDX-License-Identifier: LGPL-2.1-or-later
"""A sketch step's context: the strokes checked, the readings' scores and faces shared."""

import numpy as np
import pytest
from reading_fixtures import TOP, top_extrusion

from Sketch2CADWorkbench.brep.faces import resolve_face
from Sketch2CADWorkbench.brep.operators import apply_operation
from Sketch2CADWorkbench.brep.protocol import Extrude
from Sketch2CADWorkbench.inference import context
from Sketch2CADWorkbench.inference.context import InterpretError, check_sketch
from Sketch2CADWorkbench.inference.fitting.verify import sketch_fit


def test_a_context_scores_each_reading_once_as_verify_does(renderer, monkeypatch):
    box, op, ctx = top_extrusion(renderer)
    calls = []
    monkeypatch.setattr(
        context,
        "sketch_fit",
        lambda *a, **k: calls.append(a) or sketch_fit(*a, **k),
    )
    first = ctx.sketch_fit(box, op)
    assert ctx.sketch_fit(box, op) is first and len(calls) == 1
    want = sketch_fit(box, op, ctx.camera, ctx.strokes)
    for name in ("to_sketch", "to_strokes", "end_gaps"):
        np.testing.assert_array_equal(getattr(first, name), getattr(want, name))
    ctx.sketch_fit(box, Extrude(TOP, 4.0))
    ctx.sketch_fit(apply_operation(box, op), op)  # another solid: scored anew
    assert len(calls) == 3


def test_a_context_resolves_each_base_face_once_for_all_its_readings(renderer, monkeypatch):
    box, op, ctx = top_extrusion(renderer)
    resolved = []
    monkeypatch.setattr(context, "resolve_face", lambda *a: resolved.append(a) or resolve_face(*a))
    for d in (9.0, 4.0, -3.0):
        ctx.sketch_fit(box, Extrude(TOP, d))
    assert len(resolved) == 1
    assert ctx.resolved(box, TOP).face.isSame(resolve_face(box, TOP).face)
    other = apply_operation(box, op)
    ctx.sketch_fit(other, op)  # another solid: its own face
    assert len(resolved) == 2


@pytest.mark.parametrize(
    "strokes,message",
    [
        ([np.array([[100.0, 100.0], [100.0, 100.0]])], "span less than 3.0 pixels"),
        (
            [np.array([[0.0, 0.0], [5.0, 5.0]])] * 201,
            "201 strokes: one operation takes at most 200",
        ),
        ([np.array([[0.0, 0.0], [np.nan, 5.0]])], "not a finite number"),
        ([], "no strokes"),
    ],
)
def test_a_sketch_no_operation_can_be_read_from_is_refused_at_once(strokes, message):
    with pytest.raises(InterpretError, match=message):
        check_sketch(strokes)
