# SPDX-License-Identifier: LGPL-2.1-or-later
"""Each operator gives the analytically expected solid, and never touches its input."""

import math

import cadquery as cq
import pytest

from Sketch2CADWorkbench.brep.exchange import to_brep_text
from Sketch2CADWorkbench.brep.faces import OperationError
from Sketch2CADWorkbench.brep.operators import (
    apply_operation,
    apply_what_builds,
    boolean,
    make_box,
    operation_result,
    replay,
)
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

LX, LY, LZ = 40.0, 30.0, 20.0
BOX_VOLUME = LX * LY * LZ
TOP = FaceRef((0.0, 0.0, LZ / 2), (0.0, 0.0, 1.0))
FRONT = FaceRef((0.0, -LY / 2, 0.0), (0.0, -1.0, 0.0))
REL = 1e-6


@pytest.fixture
def box():
    return make_box(Box((LX, LY, LZ)))


def square(half, z, cx=0.0, cy=0.0):
    return (
        (cx - half, cy - half, z),
        (cx + half, cy - half, z),
        (cx + half, cy + half, z),
        (cx - half, cy + half, z),
    )


def straight(r0, r1, d):
    """Inner (r, h) control points of a straight profile c_p."""
    return ((r0 + (r1 - r0) / 3, d / 3), (r0 + 2 * (r1 - r0) / 3, 2 * d / 3))


@pytest.mark.parametrize("d", [5.0, -7.5])
def test_extrude_moves_the_face_by_d(box, d):
    out = apply_operation(box, Extrude(TOP, d))
    assert out.Volume() == pytest.approx(BOX_VOLUME + LX * LY * d, rel=REL)
    assert out.BoundingBox().zmax == pytest.approx(LZ / 2 + d)
    assert out.isValid()


def test_extrude_through_the_whole_solid_is_an_error(box):
    with pytest.raises(OperationError, match=r"empty|no volume"):
        apply_operation(box, Extrude(TOP, -LZ - 1))


def test_operator_leaves_its_input_solid_unchanged(box):
    before, text = box.Volume(), to_brep_text(box)
    apply_operation(box, Extrude(TOP, 5.0))
    apply_operation(box, AddSubPrism(TOP, square(4, LZ / 2), 3.0, Mode.SUBTRACT))
    with pytest.raises(OperationError):
        apply_operation(box, Extrude(TOP, -LZ - 1))
    assert box.Volume() == before and to_brep_text(box) == text  # not even p-curves added


@pytest.mark.parametrize("mode,sign", [(Mode.ADD, 1), (Mode.SUBTRACT, -1)])
def test_prism_adds_or_subtracts_polygon_area_times_d(box, mode, sign):
    op = AddSubPrism(TOP, square(5, LZ / 2), 8.0, mode)
    out = apply_operation(box, op)
    assert out.Volume() == pytest.approx(BOX_VOLUME + sign * 100.0 * 8.0, rel=REL)


def test_triangle_prism_volume(box):
    tri = ((0, 0, LZ / 2), (10, 0, LZ / 2), (0, 6, LZ / 2))
    out = apply_operation(box, AddSubPrism(TOP, tri, 4.0, Mode.ADD))
    assert out.Volume() == pytest.approx(BOX_VOLUME + 0.5 * 10 * 6 * 4.0, rel=REL)


def test_replace_keeps_only_the_primitive(box):
    out = apply_operation(box, AddSubPrism(TOP, square(5, LZ / 2), 8.0, Mode.REPLACE))
    assert out.Volume() == pytest.approx(100.0 * 8.0, rel=REL)


def test_intersect_keeps_the_common_part(box):
    # A subtract-direction prism does not exist for INTERSECT: it stands outwards, so
    # the intersection with the box is only the shared base face: nothing is left.
    with pytest.raises(OperationError):
        apply_operation(box, AddSubPrism(TOP, square(5, LZ / 2), 8.0, Mode.INTERSECT))


@pytest.mark.parametrize("mode,sign", [(Mode.ADD, 1), (Mode.SUBTRACT, -1)])
def test_sweep_with_straight_equal_radii_is_a_cylinder(box, mode, sign):
    r, d = 4.0, 6.0
    out = apply_operation(box, Sweep(TOP, (0, 0, LZ / 2), r, r, d, straight(r, r, d), mode))
    assert out.Volume() == pytest.approx(BOX_VOLUME + sign * math.pi * r * r * d, rel=REL)


def test_sweep_with_straight_profile_is_a_cone_frustum(box):
    r0, r1, d = 6.0, 2.0, 9.0
    out = apply_operation(box, Sweep(TOP, (3, 2, LZ / 2), r0, r1, d, straight(r0, r1, d)))
    frustum = math.pi * d / 3 * (r0 * r0 + r0 * r1 + r1 * r1)
    assert out.Volume() == pytest.approx(BOX_VOLUME + frustum, rel=REL)


def test_curved_sweep_volume_matches_pappus(box):
    """A curved profile's solid of revolution: V = pi * integral of r(h)^2 dh."""
    r0, r1, d, inner = 5.0, 3.0, 10.0, ((9.0, 3.0), (1.0, 7.0))
    out = apply_operation(box, Sweep(TOP, (0, 0, LZ / 2), r0, r1, d, inner))
    ctrl = [(r0, 0.0), *inner, (r1, d)]
    n = 4000
    vol = 0.0
    for i in range(n):  # midpoint rule on the parametric curve: pi r^2 dh/dt dt
        t = (i + 0.5) / n
        b = [(1 - t) ** 3, 3 * (1 - t) ** 2 * t, 3 * (1 - t) * t**2, t**3]
        db = [
            -3 * (1 - t) ** 2,
            3 * (1 - t) ** 2 - 6 * (1 - t) * t,
            6 * (1 - t) * t - 3 * t * t,
            3 * t * t,
        ]
        r = sum(w * p[0] for w, p in zip(b, ctrl, strict=False))
        dh = sum(w * p[1] for w, p in zip(db, ctrl, strict=False))
        vol += math.pi * r * r * dh / n
    assert out.Volume() == pytest.approx(BOX_VOLUME + vol, rel=1e-5)


def test_bevel_with_straight_profile_cuts_a_triangular_prism(box):
    c = (LX / 2, -LY / 2, LZ / 2)
    a, b = (LX / 2 - 6, -LY / 2, LZ / 2), (LX / 2, -LY / 2, LZ / 2 - 4)
    chord = (
        a,
        tuple(x + (y - x) / 3 for x, y in zip(a, b, strict=False)),
        tuple(x + 2 * (y - x) / 3 for x, y in zip(a, b, strict=False)),
        b,
    )
    out = apply_operation(box, Bevel(FRONT, c, (LX / 2, LY / 2, LZ / 2), chord))
    assert out.Volume() == pytest.approx(BOX_VOLUME - 0.5 * 6 * 4 * LY, rel=REL)


def test_rounded_bevel_removes_less_than_the_chamfer(box):
    c = (LX / 2, -LY / 2, LZ / 2)
    a, b = (LX / 2 - 6, -LY / 2, LZ / 2), (LX / 2, -LY / 2, LZ / 2 - 6)
    k = 0.5523  # quarter-circle Bezier handle length (unit radius)
    arc = (a, (LX / 2 - 6 + 6 * k, -LY / 2, LZ / 2), (LX / 2, -LY / 2, LZ / 2 - 6 + 6 * k), b)
    out = apply_operation(box, Bevel(FRONT, c, (LX / 2, LY / 2, LZ / 2), arc))
    # Region c -> a -> Bezier -> b -> c in the front face's (x, z) coordinates, by shoelace
    # over a dense sampling of the curve (close to the square minus a quarter disc).
    pts = [(c[0], c[2])]
    for i in range(2001):
        t = i / 2000
        w = [(1 - t) ** 3, 3 * (1 - t) ** 2 * t, 3 * (1 - t) * t**2, t**3]
        pts.append(
            (
                sum(wi * p[0] for wi, p in zip(w, arc, strict=False)),
                sum(wi * p[2] for wi, p in zip(w, arc, strict=False)),
            )
        )
    area = 0.5 * abs(
        sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(pts, pts[1:] + pts[:1], strict=True))
    )
    assert area == pytest.approx(36 - math.pi * 9, rel=5e-3)
    assert BOX_VOLUME - out.Volume() == pytest.approx(area * LY, rel=1e-5)


@pytest.mark.parametrize(
    "op,message",
    [
        (Extrude(FaceRef((0, 0, 99), (0, 0, 1)), 3.0), "no longer resolves"),
        (Extrude(FaceRef((0, 0, LZ / 2), (0.6, 0, 0.8)), 3.0), "no longer resolves"),
        (AddSubPrism(TOP, ((0, 0, LZ / 2), (5, 0, LZ / 2), (10, 0, LZ / 2)), 3.0), "no area"),
        (
            AddSubPrism(TOP, ((0, 0, LZ / 2), (5, 5, LZ / 2), (5, 0, LZ / 2), (0, 5, LZ / 2)), 3.0),
            "cross",
        ),
        (
            AddSubPrism(TOP, ((0, 0, LZ / 2), (5, 0, LZ / 2 + 3), (0, 5, LZ / 2)), 3.0),
            r"polygon c\[1\] lies 3 mm off",
        ),
        (Sweep(TOP, (0, 0, LZ / 2), 4.0, 4.0, 5.0, ((-9.0, 2.0), (4.0, 3.0))), "crosses the axis"),
        (
            Bevel(
                FRONT,
                (LX / 2, -LY / 2, LZ / 2),
                (LX / 2, -LY / 2, -LZ / 2),
                ((14, -15, 10), (16, -15, 10), (20, -15, 8), (20, -15, 6)),
            ),
            "crease",
        ),
        # out of the range any operator builds for a 54 mm model, said before OCCT runs
        (Extrude(TOP, 1e300), r"d = 1e\+300 mm is out of range for this model"),
        (Extrude(TOP, 1e-12), r"d = 1e-12 mm is out of range"),
        (AddSubPrism(TOP, square(4, LZ / 2), 1e-12), "out of range"),
        (Sweep(TOP, (0, 0, LZ / 2), 1e9, 4.0, 5.0, straight(1e9, 4.0, 5.0)), "r0 = 1e"),
        (AddSubPrism(TOP, ((0, 0, 1e9), (5, 0, 1e9), (0, 5, 1e9)), 3.0), "polygon lies 1e"),
        # a point on the top with the normal into the solid: not the bottom face 20 mm away
        (Extrude(FaceRef((0.0, 0.0, LZ / 2), (0.0, 0.0, -1.0)), 3.0), "points into the solid"),
        (Extrude(FaceRef((0.0, 0.0, LZ / 2), (math.nan, 0.0, 1.0)), 3.0), "unit normal"),
        # parameters no solid takes are named before f is looked for (this f is nowhere)
        (AddSubPrism(FaceRef((0, 0, 99), (0, 0, 1)), square(4, 99)[:2], 3.0), "3 to 6 vertices"),
        (AddSubPrism(FaceRef((0, 0, 99), (0, 0, 1)), square(4, 99), -3.0), "d must be positive"),
        (
            Sweep(FaceRef((0, 0, 99), (0, 0, 1)), (0, 0, 99), -4.0, 4.0, 5.0, straight(4, 4, 5)),
            "r0, r1 and d must be positive",
        ),
    ],
)
def test_unbuildable_operation_raises_operation_error_saying_why(box, op, message):
    with pytest.raises(OperationError, match=message):
        apply_operation(box, op)


def test_pocket_that_splits_the_solid_is_an_error():
    # A slot across the whole top, as deep as the box, leaves two separate halves.
    solid = make_box(Box((LX, LY, LZ)))
    slot = ((-1, -LY, LZ / 2), (1, -LY, LZ / 2), (1, LY, LZ / 2), (-1, LY, LZ / 2))
    with pytest.raises(OperationError, match="falls apart into 2 solids"):
        apply_operation(solid, AddSubPrism(TOP, slot, LZ + 5, Mode.SUBTRACT))


def test_replay_names_the_failing_step():
    tilted = FaceRef((0, 0, LZ / 2), (0.6, 0.0, 0.8))
    p = Protocol(Box((LX, LY, LZ)), (Extrude(TOP, 5.0), Extrude(tilted, 5.0)))
    with pytest.raises(OperationError, match=r"step 2 \(extrude\).*no longer resolves"):
        replay(p)


def test_face_reference_follows_an_edited_earlier_step():
    """Making the box taller moves its top face; the step on it moves along."""
    ops = (AddSubPrism(TOP, square(5, LZ / 2), 8.0, Mode.ADD),)
    tall = replay(Protocol(Box((LX, LY, LZ + 6)), ops))[-1]
    assert tall.Volume() == pytest.approx(LX * LY * (LZ + 6) + 800.0, rel=REL)
    assert tall.BoundingBox().zmax == pytest.approx((LZ + 6) / 2 + 8.0)


def test_applying_what_builds_leaves_out_a_step_whose_face_is_gone(box):
    # each step on the solid the ones before built: the post's top, raised; a step whose
    # face no longer exists (here never did) is left out, the rest still built
    post = AddSubPrism(TOP, square(5, LZ / 2), 8.0, Mode.ADD)
    raised = Extrude(FaceRef((0.0, 0.0, LZ / 2 + 8.0), (0.0, 0.0, 1.0)), 2.0)
    got = apply_what_builds(box, [post, raised])
    assert got.Volume() == pytest.approx(BOX_VOLUME + 800.0 + 200.0, rel=REL)
    gone = Extrude(FaceRef((0.0, 0.0, 100.0), (0.0, 0.0, 1.0)), 2.0)  # no face there
    with pytest.raises(OperationError):
        apply_operation(box, gone)
    assert apply_what_builds(box, [gone, post]).Volume() == pytest.approx(
        BOX_VOLUME + 800.0, rel=REL
    )


def test_replay_is_deterministic(examples_dir):
    from Sketch2CADWorkbench.brep.protocol import load

    p = load(examples_dir / "camera.json")
    a, b = replay(p), replay(p)
    assert [s.Volume() for s in a] == [s.Volume() for s in b]
    assert [len(s.Faces()) for s in a] == [len(s.Faces()) for s in b]


def test_bevel_profile_crossing_an_edge_is_refused_not_emptied(box):
    # l bulges past the left edge (x < -20) before coming back to it: the removed region
    # would cross itself.
    bulging = ((-14.0, -15.0, 10.0), (-17.3, -15.0, 10.1), (-20.4, -15.0, 7.3), (-20.0, -15.0, 4.0))
    with pytest.raises(OperationError, match="leaves the corner's region"):
        apply_operation(box, Bevel(FRONT, (-20, -15, 10), (-20, 15, 10), bulging))


def test_a_bevel_whose_corner_is_inside_f_is_refused_naming_the_corner():
    # the middle of the front face of a 60 x 20 x 40 box; l reaches 5 mm from it, and
    # the box's corner at (-30, -10, 20) has its edges along l's ends
    box = make_box(Box((60.0, 20.0, 40.0)))
    front = FaceRef((0.0, -10.0, 0.0), (0.0, -1.0, 0.0))
    profile = ((0.0, -10.0, -5.0), (0.0, -10.0, -2.0), (2.0, -10.0, 0.0), (5.0, -10.0, 0.0))
    with pytest.raises(OperationError, match=r"corner c \(0, -10, 0\) lies inside face f"):
        apply_operation(box, Bevel(front, (0.0, -10.0, 0.0), (0.0, 10.0, 0.0), profile))


def test_a_sweep_profile_whose_height_folds_back_is_refused_naming_the_profile(box):
    folding = Sweep(TOP, (0.0, 0.0, LZ / 2), 5.0, 5.0, 10.0, ((6.0, 30.0), (6.0, -20.0)))
    with pytest.raises(OperationError, match="profile c_p folds back"):
        apply_operation(box, folding)
    # a profile bulging outwards (r not monotonic) with h rising builds
    bulge = Sweep(TOP, (0.0, 0.0, LZ / 2), 5.0, 5.0, 10.0, ((9.0, 3.0), (9.0, 7.0)))
    assert apply_operation(box, bulge).isValid()


@pytest.mark.parametrize(
    "op,boolean,name",
    [
        (Extrude(TOP, 5.0), Mode.ADD, "extrude"),
        (Extrude(TOP, -5.0), Mode.SUBTRACT, "extrude"),
        (
            Bevel(
                FRONT,
                (-20, -15, 10),
                (-20, 15, 10),
                ((-14, -15, 10), (-16, -15, 10), (-20, -15, 8), (-20, -15, 6)),
            ),
            Mode.SUBTRACT,
            "bevel",
        ),
        (
            AddSubPrism(TOP, square(4, LZ / 2), 3.0, Mode.INTERSECT),
            Mode.INTERSECT,
            "intersect prism",
        ),
        (
            Sweep(TOP, (0, 0, LZ / 2), 4.0, 4.0, 5.0, straight(4, 4, 5), Mode.SUBTRACT),
            Mode.SUBTRACT,
            "subtract sweep",
        ),
    ],
)
def test_every_operation_ends_in_the_boolean_it_names(op, boolean, name):
    assert (op.boolean, op.name) == (boolean, name)


def test_a_resolved_face_taken_from_the_solid_is_what_resolving_its_reference_finds(box):
    from Sketch2CADWorkbench.brep.faces import ResolvedFace, face_ref_of, resolve_face

    for face in box.Faces():
        found, held = resolve_face(box, face_ref_of(face)), ResolvedFace.of(face)
        assert found.face.isSame(held.face) and found.shift == held.shift == 0.0
        assert (found.normal == held.normal).all()


def test_an_operation_given_a_face_of_another_solid_or_a_curved_reference_is_refused(box):
    other = make_box(Box((LX, LY, LZ)))
    with pytest.raises(ValueError, match="not a face of the solid"):
        apply_operation(box, Extrude(TOP, 5.0), other.Faces()[5])
    curved = FaceRef((0.0, 0.0, LZ / 2), (0.0, 0.0, 1.0), Surface.CYLINDER)
    with pytest.raises(ValueError, match="must be planar"):
        apply_operation(box, Extrude(curved, 5.0), box.Faces()[5])


def test_an_operation_result_carries_its_solid_s_volume(box):
    out = operation_result(box, AddSubPrism(TOP, square(4, LZ / 2), 3.0, Mode.SUBTRACT))
    assert out.volume == out.solid.Volume() == pytest.approx(BOX_VOLUME - 8 * 8 * 3, rel=REL)


@pytest.mark.parametrize(
    "mode,cadquery_op", [(Mode.ADD, "fuse"), (Mode.SUBTRACT, "cut"), (Mode.INTERSECT, "intersect")]
)
@pytest.mark.parametrize("compound", [False, True])
def test_the_operators_boolean_gives_what_cadquery_s_gives(mode, cadquery_op, compound):
    """The OCCT options `boolean` sets change its cost, not its result, on a solid or a
    compound (whose shapes cadquery passes on in its place)."""

    def inputs():
        body = make_box(Box((LX, LY, LZ))).cut(
            cq.Solid.makeCylinder(4, LZ * 2, cq.Vector(8, 0, -LZ))
        )
        return (body if compound else body.Solids()[0]), cq.Solid.makeCone(
            9, 3, LZ, cq.Vector(-5, 2, 0)
        )

    body, tool = inputs()
    ours = boolean(body, tool, mode)
    body, tool = inputs()
    assert to_brep_text(ours) == to_brep_text(getattr(body, cadquery_op)(tool))


def test_build_holds_only_the_solid_of_the_step_it_builds(box, monkeypatch):
    # a long protocol's replay must not keep every step's solid (memory grows with the
    # square of the steps: each holds the faces of all before it)
    import gc
    import weakref

    from Sketch2CADWorkbench.brep import operators

    made, alive = [], []
    result = operators.operation_result

    def tracked(solid, op, face=None, check_valid=True):
        out = result(solid, op, face, check_valid)
        made.append(weakref.ref(out.solid))
        return out

    monkeypatch.setattr(operators, "operation_result", tracked)

    def step(i):
        gc.collect()
        alive.append(sum(r() is not None for r in made))

    ops = tuple(
        AddSubPrism(TOP, square(1.0, LZ / 2, -15 + 6 * k), 2.0, Mode.SUBTRACT) for k in range(5)
    )
    operators.build(Protocol(Box((LX, LY, LZ)), ops), on_step=step)
    assert max(alive) == 1, alive


def test_build_and_replay_give_what_checking_every_step_gives(examples_dir):
    # replay checks OCCT's validity once, at the end: each example's solids are still the
    # ones that applying its operations one by one, each checked, builds
    from Sketch2CADWorkbench.brep.operators import build
    from Sketch2CADWorkbench.brep.protocol import load

    for path in sorted(examples_dir.glob("*.json")):
        p = load(path)
        stepwise = [make_box(p.base)]
        for op in p.operations:
            stepwise.append(apply_operation(stepwise[-1], op))
        texts = [to_brep_text(s) for s in stepwise]
        assert [to_brep_text(s) for s in replay(p)] == texts, path.name
        assert to_brep_text(build(p)) == texts[-1], path.name


def holes_protocol(count, last=None):
    """The box with `count` square holes in its top, then `last` if given."""
    ops = tuple(
        AddSubPrism(TOP, square(1.0, LZ / 2, -15 + 6 * k), 2.0, Mode.SUBTRACT) for k in range(count)
    )
    return Protocol(Box((LX, LY, LZ)), ops + ((last,) if last else ()))


def report_invalid(monkeypatch, bad):
    """OCCT's validity check reports a solid invalid where bad(its volume) holds."""
    monkeypatch.setattr(cq.Shape, "isValid", lambda self: not bad(self.Volume()))


@pytest.mark.parametrize("run", ["replay", "build"])
def test_an_invalid_step_is_named_though_only_the_end_is_checked(monkeypatch, run):
    from Sketch2CADWorkbench.brep import operators

    p = holes_protocol(4)
    after_two = replay(p)[2].Volume()
    # invalid from step 2 on, as an invalid solid stays invalid under later Booleans
    report_invalid(monkeypatch, lambda v: v <= after_two + 1e-6)
    with pytest.raises(OperationError, match=r"^step 2 \(addsub\): .*invalid solid"):
        getattr(operators, run)(p)


def test_an_invalid_solid_a_step_replaces_is_still_named(monkeypatch):
    from Sketch2CADWorkbench.brep.operators import build

    # step 3 replaces the solid by its prism, which would hide step 2's invalid solid
    post = AddSubPrism(TOP, square(5, LZ / 2), 8.0, Mode.REPLACE)
    p = holes_protocol(2, post)
    after_two = replay(p)[2].Volume()
    report_invalid(monkeypatch, lambda v: abs(v - after_two) < 1e-6)
    with pytest.raises(OperationError, match=r"^step 2 \(addsub\): .*invalid solid"):
        build(p)
