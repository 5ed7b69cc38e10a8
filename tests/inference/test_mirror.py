# SPDX-License-Identifier: LGPL-2.1-or-later
"""A step applied with its mirror image."""

import pytest
from reading_fixtures import TOP, Oracle, sketch, view

from Sketch2CADWorkbench.brep.operators import apply_operation, make_box
from Sketch2CADWorkbench.brep.protocol import AddSubPrism, Bevel, Box, FaceRef, Mode
from Sketch2CADWorkbench.inference.interpret import interpret
from Sketch2CADWorkbench.inference.mirror import apply_with_symmetry
from Sketch2CADWorkbench.inference.options import InterpretOptions


def test_mirror_option_adds_the_reflected_prism(renderer):
    box = make_box(Box((40, 30, 20)))
    op = AddSubPrism(TOP, ((6, -5, 10), (14, -5, 10), (14, 5, 10), (6, 5, 10)), 6.0, Mode.ADD)
    cam = view()
    pts, labels = sketch(box, op, cam)
    oracle = Oracle(box, op, pts, labels, cam, renderer)
    got = interpret(
        box, [cam.project(p)[0] for p in pts], cam, oracle, renderer, InterpretOptions(symmetry="x")
    )
    assert len(got.operations) == 2
    bb = got.solid.BoundingBox()
    assert bb.zmax == pytest.approx(16.0, abs=0.5)
    xs = [v.X for v in got.solid.Vertices() if abs(v.Z - bb.zmax) < 1e-6]
    assert min(xs) == pytest.approx(-max(xs), abs=1e-6)  # two prisms, mirror images


def test_a_bevel_along_a_whole_edge_the_plane_halves_is_not_mirrored_onto_itself():
    box = make_box(Box((40, 30, 20)))
    # the front face's top-right corner rounded through the whole depth (y = -15 to 15)
    op = Bevel(
        FaceRef((0, -15, 0), (0, -1, 0)),
        (20, -15, 10),
        (20, 15, 10),
        ((16, -15, 10), (18.2, -15, 10), (20, -15, 8.2), (20, -15, 6)),
    )
    alone = apply_operation(box, op)
    ops, result = apply_with_symmetry(box, op, "y")
    assert ops == (op,) and result.Volume() == pytest.approx(alone.Volume(), rel=1e-9)
    ops, result = apply_with_symmetry(box, op, "x")  # the other side's edge: mirrored
    assert len(ops) == 2
    assert box.Volume() - result.Volume() == pytest.approx(
        2 * (box.Volume() - alone.Volume()), rel=1e-6
    )
