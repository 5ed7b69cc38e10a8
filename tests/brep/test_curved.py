# SPDX-License-Identifier: LGPL-2.1-or-later
"""Operators on curved faces (beyond the paper): a boss, slot, peg or drilled hole
standing on a cylinder's side meets the curved wall as a designer expects, an extrusion
of a cylinder's side changes its radius, and anything else is a clear error."""

import math

import cadquery as cq
import pytest

from Sketch2CADWorkbench.brep.faces import OperationError, resolve_face
from Sketch2CADWorkbench.brep.operators import apply_operation, replay
from Sketch2CADWorkbench.brep.protocol import (
    AddSubPrism,
    Bevel,
    Box,
    Extrude,
    FaceRef,
    Mode,
    Protocol,
    Surface,
    Sweep,
)

R, H = 10.0, 60.0  # a rod along z from z=0 to z=60
CYL = Surface.CYLINDER
SIDE = FaceRef((R, 0.0, 30.0), (1.0, 0.0, 0.0), CYL)  # the rod's side, facing +x


def straight(r0, r1, d):
    return ((r0 + (r1 - r0) / 3, d / 3), (r0 + 2 * (r1 - r0) / 3, 2 * d / 3))


def rod(radius=R):
    return cq.Solid.makeCylinder(radius, H, cq.Vector(0, 0, 0), cq.Vector(0, 0, 1))


def tube(outer=R, inner=6.0):
    return rod(outer).cut(rod(inner)).Solids()[0]


def rectangle(half_w, half_l, x=R, z=30.0):
    """A rectangle on the tangent plane x = `x`: half_w across the axis (y), half_l along
    it (z)."""
    return (
        (x, -half_w, z - half_l),
        (x, half_w, z - half_l),
        (x, half_w, z + half_l),
        (x, -half_w, z + half_l),
    )


def segment_area(a, r=R):
    """Area between the chord |y| <= a of the tangent line and a circle of radius r: the
    cylinder's sagitta integrated across the footprint."""
    return 2 * a * r - (a * math.sqrt(r * r - a * a) + r * r * math.asin(a / r))


def test_a_boss_on_a_rod_meets_the_curved_side_without_a_gap():
    a, l, d = 4.0, 5.0, 3.0
    out = apply_operation(rod(), AddSubPrism(SIDE, rectangle(a, l), d, Mode.ADD))
    assert out.isValid()
    # the prism d above the tangent plane, plus the wedge down to the curved wall
    added = out.Volume() - rod().Volume()
    assert added == pytest.approx(2 * l * (2 * a * d + segment_area(a)), rel=1e-6)
    assert out.BoundingBox().xmax == pytest.approx(R + d)
    # just above the wall under the boss's edge is material: no gap
    assert out.isInside(cq.Vector(math.sqrt(R * R - 3.9**2) + 0.05, 3.9, 30.0))


def test_a_slot_in_a_rod_is_d_deep_below_the_point_it_stands_on():
    a, l, d = 3.0, 6.0, 2.0
    out = apply_operation(rod(), AddSubPrism(SIDE, rectangle(a, l), d, Mode.SUBTRACT))
    removed = rod().Volume() - out.Volume()
    # the slot's floor is the plane x = R - d; what is cut is under the curved wall
    assert removed == pytest.approx(2 * l * (2 * a * d - segment_area(a)), rel=1e-6)
    assert not out.isInside(cq.Vector(R - d + 0.05, 0.0, 30.0))
    assert out.isInside(cq.Vector(R - d - 0.05, 0.0, 30.0))


def test_a_radial_peg_on_a_tube_and_a_hole_drilled_into_its_bore():
    r, d = 3.0, 8.0
    peg = apply_operation(tube(), Sweep(SIDE, SIDE.point, r, r, d, straight(r, r, d)))
    added = peg.Volume() - tube().Volume()
    sagitta = R - math.sqrt(R * R - r * r)
    assert math.pi * r * r * d < added < math.pi * r * r * (d + sagitta)
    assert peg.BoundingBox().xmax == pytest.approx(R + d)
    assert peg.isInside(cq.Vector(R - sagitta + 0.1, 2.9, 30.0))  # under the peg's rim
    assert not peg.isInside(cq.Vector(5.0, 0.0, 30.0))  # the bore stays open
    hole = apply_operation(
        tube(), Sweep(SIDE, SIDE.point, 2.0, 2.0, 5.0, straight(2, 2, 5), Mode.SUBTRACT)
    )
    assert hole.isValid()
    assert not hole.isInside(cq.Vector(8.0, 0.0, 30.0))  # through the wall into the bore
    assert hole.isInside(cq.Vector(8.0, 0.0, 25.0))


def test_extruding_a_cylinders_side_changes_its_radius_by_d():
    grown = apply_operation(rod(), Extrude(SIDE, 2.0))
    assert grown.Volume() == pytest.approx(math.pi * (R + 2) ** 2 * H, rel=1e-6)
    shrunk = apply_operation(rod(), Extrude(SIDE, -2.5))
    assert shrunk.Volume() == pytest.approx(math.pi * (R - 2.5) ** 2 * H, rel=1e-6)
    bore = FaceRef((6.0, 0.0, 30.0), (-1.0, 0.0, 0.0), CYL)  # the tube's bore faces the axis
    narrowed = apply_operation(tube(), Extrude(bore, 1.0))  # the wall moves 1 mm inwards
    assert narrowed.Volume() == pytest.approx(math.pi * (R * R - 25.0) * H, rel=1e-6)


def test_a_rib_inside_a_tubes_bore_stands_on_the_concave_wall():
    bore = FaceRef((-6.0, 0.0, 30.0), (1.0, 0.0, 0.0), CYL)
    rib = ((-6.0, -1.0, 20.0), (-6.0, 1.0, 20.0), (-6.0, 1.0, 40.0), (-6.0, -1.0, 40.0))
    out = apply_operation(tube(), AddSubPrism(bore, rib, 2.0, Mode.ADD))
    added = out.Volume() - tube().Volume()
    # the rib is 2 mm tall at its centre; the wall curves up towards its sides
    assert 20 * 2 * 2.0 - 20 * segment_area(1.0, 6.0) == pytest.approx(added, rel=1e-6)


def test_a_cone_side_takes_a_boss_too():
    cone = cq.Solid.makeCone(12.0, 6.0, 40.0, cq.Vector(0, 0, 0), cq.Vector(0, 0, 1))
    slope = 6.0 / 40.0
    n = (1 / math.sqrt(1 + slope**2), 0.0, slope / math.sqrt(1 + slope**2))
    p = (9.0, 0.0, 20.0)
    u = (-n[2], 0.0, n[0])  # along the cone's side, in the tangent plane
    square = tuple(
        (p[0] + s * u[0], t, p[2] + s * u[2]) for s, t in ((-2, -2), (2, -2), (2, 2), (-2, 2))
    )
    out = apply_operation(cone, AddSubPrism(FaceRef(p, n, Surface.CONE), square, 2.0))
    assert out.isValid() and out.Volume() > cone.Volume() + 4 * 4 * 2.0


@pytest.mark.parametrize(
    "op, message",
    [
        (AddSubPrism(SIDE, rectangle(11.0, 3.0), 2.0), r"narrower than the cylinder"),
        (
            AddSubPrism(SIDE, rectangle(3.0, 3.0), 2.0, Mode.INTERSECT),
            r"intersect on a curved face f is not supported",
        ),
        (Extrude(SIDE, -10.0), r"\|d\| must stay under the radius"),
        (
            Bevel(
                SIDE,
                (R, 0.0, 30.0),
                (R, 0.0, 20.0),
                ((R, 1.0, 30.0), (R, 1.0, 29.0), (R, 0.0, 29.0), (R, 0.0, 28.0)),
            ),
            r"a bevel rounds a corner of a planar face",
        ),
        (
            AddSubPrism(FaceRef((R, 0.0, 30.0), (1.0, 0.0, 0.0)), rectangle(2.0, 2.0), 2.0),
            r"no planar face",
        ),
        (
            AddSubPrism(FaceRef((0.0, 0.0, H), (0.0, 0.0, 1.0), CYL), rectangle(2.0, 2.0), 2.0),
            r"no cylinder face",
        ),
    ],
)
def test_what_cannot_stand_on_a_curved_face_is_a_clear_error(op, message):
    with pytest.raises(OperationError, match=message):
        apply_operation(rod(), op)


PIPE = Protocol(
    Box((40.0, 40.0, 20.0)),
    (
        Sweep(
            FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0)),
            (0.0, 0.0, 10.0),
            R,
            R,
            H,
            straight(R, R, H),
            Mode.REPLACE,
        ),
        Sweep(
            FaceRef((0.0, 0.0, 70.0), (0.0, 0.0, 1.0)),
            (0.0, 0.0, 70.0),
            6.0,
            6.0,
            H,
            straight(6, 6, H),
            Mode.SUBTRACT,
        ),
        Sweep(
            FaceRef((R, 0.0, 40.0), (1.0, 0.0, 0.0), CYL),
            (R, 0.0, 40.0),
            3.0,
            3.0,
            8.0,
            straight(3, 3, 8),
        ),
        AddSubPrism(
            FaceRef((0.0, -R, 30.0), (0.0, -1.0, 0.0), CYL),
            ((-2.0, -R, 27.0), (2.0, -R, 27.0), (2.0, -R, 33.0), (-2.0, -R, 33.0)),
            2.0,
        ),
    ),
)


def test_a_step_on_a_cylinders_side_follows_an_edit_of_its_radius():
    before = replay(PIPE)[-1]
    wider = Protocol(
        PIPE.base,
        (
            Sweep(
                PIPE.operations[0].face,
                (0.0, 0.0, 10.0),
                13.0,
                13.0,
                H,
                straight(13, 13, H),
                Mode.REPLACE,
            ),
            *PIPE.operations[1:],
        ),
    )
    after = replay(wider)[-1]
    bb0, bb1 = before.BoundingBox(), after.BoundingBox()
    # the peg and the boss moved out with the wall, keeping their height above it
    assert bb1.xmax == pytest.approx(bb0.xmax + 3.0)
    assert bb1.ymin == pytest.approx(bb0.ymin - 3.0)
    rf = resolve_face(replay(wider)[2], PIPE.operations[2].face)
    assert rf.shift == pytest.approx(3.0) and rf.point.tolist() == pytest.approx([13, 0, 40])


def test_a_step_on_a_side_that_is_no_longer_there_goes_into_error_saying_so():
    box = cq.Solid.makeBox(20.0, 20.0, 60.0, cq.Vector(-10.0, -10.0, 0.0))  # planar sides
    with pytest.raises(OperationError, match="no cylinder face has that outward normal"):
        apply_operation(box, PIPE.operations[2])
