# SPDX-License-Identifier: LGPL-2.1-or-later
"""Editing an earlier step moves the later steps as a CAD user expects: each
operator after an edit of each earlier kind of step keeps its shape and follows the face
it was sketched on, or goes into error saying why it no longer fits."""

import math

import cadquery as cq
import pytest

from Sketch2CADWorkbench.brep.faces import OperationError, resolve_face
from Sketch2CADWorkbench.brep.operators import locate_bevel, replay
from Sketch2CADWorkbench.brep.protocol import (
    AddSubPrism,
    Bevel,
    Box,
    Extrude,
    FaceRef,
    Mode,
    Protocol,
    Sweep,
)

BOX = Box((40.0, 30.0, 20.0))  # z from -10 to 10
TOP = FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0))
FRONT = FaceRef((0.0, -15.0, 0.0), (0.0, -1.0, 0.0))
REL = 1e-6


def square(half, z, cx=0.0, cy=0.0):
    return (
        (cx - half, cy - half, z),
        (cx + half, cy - half, z),
        (cx + half, cy + half, z),
        (cx - half, cy + half, z),
    )


def straight(r0, r1, d):
    return ((r0 + (r1 - r0) / 3, d / 3), (r0 + 2 * (r1 - r0) / 3, 2 * d / 3))


def round_corner(face, corner, along_a, along_b, opposite, r):
    """A quarter-round-like bevel of corner c on face f: l from r along edge a to r along
    edge b, its inner control points pulled towards c."""
    c = tuple(corner)
    pa = tuple(ci + r * ai for ci, ai in zip(c, along_a, strict=False))
    pb = tuple(ci + r * bi for ci, bi in zip(c, along_b, strict=False))
    inner = [tuple(p + 0.55 * (ci - p) for p, ci in zip(q, c, strict=False)) for q in (pa, pb)]
    return Bevel(face, c, tuple(opposite), (pa, inner[0], inner[1], pb))


# The earlier steps: (box, steps as sketched, box and steps after the edit, the face the
# later steps are sketched on and its height, how far that face moves, and a corner of a
# side face (face, corner, its edge directions, crease end) for a later bevel, with how
# far that corner moves).
COLUMN_TOP = FaceRef((0.0, 0.0, 18.0), (0.0, 0.0, 1.0))
COLUMN_FRONT = FaceRef((0.0, -8.0, 14.0), (0.0, -1.0, 0.0))
EARLIER = {
    "box": dict(
        box=BOX,
        steps=(),
        edited_box=Box((40.0, 30.0, 26.0)),
        edited=(),
        face=TOP,
        z=10.0,
        dz=3.0,
        at=(0.0, 0.0),
        bevel=(FRONT, (20.0, -15.0, 10.0), (-1, 0, 0), (0, 0, -1), (20.0, 15.0, 10.0)),
        bevel_dz=3.0,
    ),
    "extrude": dict(
        box=BOX,
        steps=(Extrude(TOP, 6.0),),
        edited_box=BOX,
        edited=(Extrude(TOP, 11.0),),
        face=FaceRef((0.0, 0.0, 16.0), (0.0, 0.0, 1.0)),
        z=16.0,
        dz=5.0,
        at=(0.0, 0.0),
        bevel=(FRONT, (20.0, -15.0, 16.0), (-1, 0, 0), (0, 0, -1), (20.0, 15.0, 16.0)),
        bevel_dz=5.0,
    ),
    "prism": dict(
        box=BOX,
        steps=(AddSubPrism(TOP, square(8.0, 10.0), 8.0),),
        edited_box=BOX,
        edited=(AddSubPrism(TOP, square(8.0, 10.0), 13.0),),
        face=COLUMN_TOP,
        z=18.0,
        dz=5.0,
        at=(0.0, 0.0),
        bevel=(COLUMN_FRONT, (8.0, -8.0, 18.0), (-1, 0, 0), (0, 0, -1), (8.0, 8.0, 18.0)),
        bevel_dz=5.0,
    ),
    "sweep": dict(
        box=BOX,
        steps=(Sweep(TOP, (0.0, 0.0, 10.0), 8.0, 8.0, 8.0, straight(8, 8, 8)),),
        edited_box=BOX,
        edited=(Sweep(TOP, (0.0, 0.0, 10.0), 8.0, 8.0, 13.0, straight(8, 8, 13)),),
        face=COLUMN_TOP,
        z=18.0,
        dz=5.0,
        at=(0.0, 0.0),
        # the cylinder has no corner: a bevel of the box's corner, which the edit leaves
        bevel=(FRONT, (20.0, -15.0, 10.0), (-1, 0, 0), (0, 0, -1), (20.0, 15.0, 10.0)),
        bevel_dz=0.0,
    ),
    "bevel": dict(
        box=BOX,
        steps=(
            round_corner(
                TOP, (-20.0, -15.0, 10.0), (1, 0, 0), (0, 1, 0), (-20.0, -15.0, -10.0), 6.0
            ),
        ),
        edited_box=BOX,
        edited=(
            round_corner(
                TOP, (-20.0, -15.0, 10.0), (1, 0, 0), (0, 1, 0), (-20.0, -15.0, -10.0), 10.0
            ),
        ),
        face=TOP,
        z=10.0,
        dz=0.0,
        at=(8.0, 5.0),
        bevel=(FRONT, (20.0, -15.0, 10.0), (-1, 0, 0), (0, 0, -1), (20.0, 15.0, 10.0)),
        bevel_dz=0.0,
    ),
}


def later_step(kind: str, e: dict):
    """The later step of `kind` on the earlier step's face (or corner, for a bevel)."""
    z, (cx, cy) = e["z"], e["at"]
    if kind == "extrude":
        return Extrude(e["face"], 4.0)
    if kind == "prism":
        return AddSubPrism(e["face"], square(3.0, z, cx, cy), 5.0, Mode.ADD)
    if kind == "sweep":
        return Sweep(e["face"], (cx, cy, z), 2.0, 3.0, 5.0, straight(2, 3, 5), Mode.ADD)
    face, corner, a, b, opposite = e["bevel"]
    return round_corner(face, corner, a, b, opposite, 4.0)


def build_both(e: dict, later):
    """The solids before and after the later step, as sketched and after the edit."""
    before = replay(Protocol(e["box"], e["steps"] + (later,)))
    after = replay(Protocol(e["edited_box"], e["edited"] + (later,)))
    return before[-2:], after[-2:]


@pytest.mark.parametrize("later_kind", ["extrude", "bevel", "prism", "sweep"])
@pytest.mark.parametrize("earlier", sorted(EARLIER))
def test_a_later_step_follows_an_edit_of_an_earlier_one(earlier, later_kind):
    e = EARLIER[earlier]
    later = later_step(later_kind, e)
    (b0, b1), (a0, a1) = build_both(e, later)
    change_before, change_after = b1.Volume() - b0.Volume(), a1.Volume() - a0.Volume()
    if later_kind == "extrude":
        # the face is padded by 4 mm wherever it is now: its area times 4
        area = resolve_face(a0, later.face).face.Area()
        assert change_after == pytest.approx(4.0 * area, rel=REL)
        assert a1.BoundingBox().zmax == pytest.approx(e["z"] + e["dz"] + 4.0, abs=1e-5)
    elif later_kind == "bevel":
        # the same round on the same corner, wherever the corner is now
        assert change_after == pytest.approx(change_before, rel=REL) and change_before < 0
        moved = locate_bevel(a0, later)
        assert moved.corner == pytest.approx(
            (later.corner[0], later.corner[1], later.corner[2] + e["bevel_dz"]), abs=1e-9
        )
        assert sum(moved.profile, ()) == pytest.approx(
            sum(((x, y, z + e["bevel_dz"]) for x, y, z in later.profile), ()), abs=1e-9
        )
    else:
        # the primitive keeps its size and stands on the face where it is now
        assert change_after == pytest.approx(change_before, rel=REL) and change_before > 0
        assert a1.BoundingBox().zmax == pytest.approx(e["z"] + e["dz"] + 5.0, abs=1e-5)


def test_the_reported_case_a_bevel_under_a_longer_extrusion_moves_to_the_new_top():
    """The Extrude's offset from 9.54 to 15 mm used to leave both rounds as grooves 5 mm
    below the new top, and every step said it was valid."""
    bevel = round_corner(
        FRONT, (20.0, -15.0, 19.54), (-1, 0, 0), (0, 0, -1), (20.0, 15.0, 19.54), 5.0
    )
    solids = replay(Protocol(BOX, (Extrude(TOP, 15.0), bevel)))
    assert locate_bevel(solids[1], bevel).corner == pytest.approx((20.0, -15.0, 25.0))
    # the corner itself is rounded off: nothing of the solid right at the new top corner
    assert not solids[2].isInside(cq.Vector(19.9, 0.0, 24.9))
    assert solids[2].isInside(cq.Vector(19.9, 0.0, 19.0))


def test_a_bevel_whose_corner_no_longer_fits_goes_into_error_saying_why():
    # a round reaching 4 mm along the column top's edges; the column made 3 mm wide
    bevel = round_corner(
        COLUMN_TOP, (8.0, -8.0, 18.0), (-1, 0, 0), (0, 1, 0), (8.0, -8.0, 10.0), 4.0
    )
    column = AddSubPrism(TOP, square(8.0, 10.0), 8.0)
    assert len(replay(Protocol(BOX, (column, bevel)))) == 3
    thin = AddSubPrism(TOP, square(1.5, 10.0), 8.0)
    with pytest.raises(
        OperationError,
        match=r"step 2 \(bevel\): bevel: profile l ends 4 mm "
        r"from corner c \(1.5, -1.5, 18\) along an edge of "
        r"f that is 3 mm long",
    ):
        replay(Protocol(BOX, (thin, bevel)))
    # a triangular column: the corner is there, but one of its edges runs elsewhere
    triangle = AddSubPrism(TOP, ((-8.0, -8.0, 10.0), (8.0, -8.0, 10.0), (0.0, 8.0, 10.0)), 8.0)
    with pytest.raises(
        OperationError,
        match=r"the end l\(1\) of profile l \(8, -4, 18\) is "
        r"not on an edge of f that meets at corner c",
    ):
        replay(Protocol(BOX, (triangle, bevel)))
    # a column turned by 45 degrees: no corner of f has its edges along l's ends
    diamond = AddSubPrism(
        TOP, ((0.0, -9.0, 10.0), (9.0, 0.0, 10.0), (0.0, 9.0, 10.0), (-9.0, 0.0, 10.0)), 8.0
    )
    with pytest.raises(OperationError, match=r"corner c \(8, -8, 18\) is not a corner of face f"):
        replay(Protocol(BOX, (diamond, bevel)))


def test_a_bevel_whose_corner_is_not_a_vertex_of_the_face_is_refused_naming_it():
    """c in the middle of the front face's top edge, with a 1 mm crease that
    no corner of f has, is refused (not built, and not moved to a corner)."""
    op = Bevel(
        FRONT,
        (15.0, -15.0, 10.0),
        (15.0, -14.0, 10.0),
        ((14.0, -15.0, 10.0), (15.0, -15.0, 10.0), (15.0, -15.0, 9.0), (15.0, -15.0, 8.0)),
    )
    with pytest.raises(
        OperationError,
        match=r"corner c \(15, -15, 10\) is not a corner of "
        "face f",
    ):
        replay(Protocol(BOX, (op,)))


def test_a_bevel_follows_a_deeper_box_along_its_crease():
    """The crease runs along the solid's edge to its far end: a deeper box bevels the whole
    of the longer edge (c' is where the crease ended when the step was made)."""
    bevel = round_corner(
        FRONT, (20.0, -15.0, 10.0), (-1, 0, 0), (0, 0, -1), (20.0, 15.0, 10.0), 4.0
    )
    shallow = replay(Protocol(BOX, (bevel,)))
    deep = replay(Protocol(Box((40.0, 50.0, 20.0)), (bevel,)))  # front face at y = -25
    removed = [s[0].Volume() - s[1].Volume() for s in (shallow, deep)]
    assert removed[1] == pytest.approx(removed[0] * 50.0 / 30.0, rel=REL)
    assert locate_bevel(deep[0], bevel).opposite == pytest.approx((20.0, 25.0, 10.0))
    assert math.isclose(locate_bevel(shallow[0], bevel).corner[1], -15.0)


def test_the_mixers_rounded_plate_follows_a_longer_column(examples_dir):
    """The document check's edit: the column under the top plate made 10 mm longer. The
    plate's round (step 7) used to stay 10 mm below the plate's new top edge."""
    from dataclasses import replace

    from Sketch2CADWorkbench.brep.protocol import load

    p = load(examples_dir / "mixer.json")
    ops = list(p.operations)
    ops[0] = replace(ops[0], d=ops[0].d + 10.0)
    before, after = replay(p), replay(Protocol(p.base, tuple(ops)))
    removed = [s[6].Volume() - s[7].Volume() for s in (before, after)]
    assert removed[1] == pytest.approx(removed[0], rel=REL)
    assert locate_bevel(after[6], ops[6]).corner == pytest.approx((35.0, -16.0, 96.0))
