# SPDX-License-Identifier: LGPL-2.1-or-later
"""Symmetry mirrors operations exactly through the model's mid-plane."""

import pytest

from Sketch2CADWorkbench.brep.operators import apply_operation, make_box
from Sketch2CADWorkbench.brep.protocol import AddSubPrism, Box, FaceRef, Mode, Sweep
from Sketch2CADWorkbench.brep.symmetry import mid_plane, reflect


def test_mirrored_prism_lands_on_the_opposite_side_with_equal_volume():
    box = make_box(Box((40, 30, 20)))
    op = AddSubPrism(
        FaceRef((0, 0, 10), (0, 0, 1)),
        ((8, 3, 10), (16, 3, 10), (16, 9, 10), (8, 9, 10)),
        5.0,
        Mode.ADD,
    )
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
    op = Sweep(
        FaceRef((20, 0, 0), (1, 0, 0)), (20, 4, 2), 3.0, 3.0, 6.0, ((3, 2), (3, 4)), Mode.ADD
    )
    mirrored = reflect(op, *mid_plane(box, "x"))
    assert mirrored.face.normal == pytest.approx((-1, 0, 0))
    out = apply_operation(apply_operation(box, op), mirrored)
    assert (out.BoundingBox().xmin, out.BoundingBox().xmax) == pytest.approx((-26, 26))
