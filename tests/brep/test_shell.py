# SPDX-License-Identifier: LGPL-2.1-or-later
"""The shell: its protocol version, OCCT's thick solid, and the thicknesses it refuses."""

import json
import math

import pytest

from Sketch2CADWorkbench.brep.operators import apply_operation, make_box, replay
from Sketch2CADWorkbench.brep.protocol import (
    Bevel,
    Box,
    FaceRef,
    Mode,
    OperationError,
    Protocol,
    ProtocolError,
    Shell,
    Sweep,
    load,
    loads,
    protocol_to_dict,
    straight_profile,
)

BOX = Box((40.0, 30.0, 20.0))
TOP = FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0))
BOTTOM = FaceRef((0.0, 0.0, -10.0), (0.0, 0.0, -1.0))


def test_a_shell_is_written_as_version_3_and_reads_back():
    p = Protocol(BOX, (Shell(TOP, 2.0),))
    d = protocol_to_dict(p)
    assert d["version"] == 3
    assert d["operations"] == [{"type": "shell", "face": TOP.to_dict(), "t": 2.0}]
    assert loads(p.to_json()) == p


def test_protocols_without_a_shell_keep_their_version(examples_dir):
    for f in examples_dir.glob("*.json"):
        p = load(f)
        has_shell = any(isinstance(op, Shell) for op in p.operations)
        expected = json.loads(f.read_text())["version"]
        assert protocol_to_dict(p)["version"] == (3 if has_shell else expected), f.name


@pytest.mark.parametrize("version", [1, 2])
def test_a_shell_in_an_older_version_is_refused_by_name(version):
    d = protocol_to_dict(Protocol(BOX, (Shell(TOP, 2.0),)))
    d["version"] = version
    with pytest.raises(ProtocolError, match=r"operations\[0\]\.type: a shell needs version 3"):
        loads(json.dumps(d))


@pytest.mark.parametrize("t", [0, -1.5, "2"])
def test_a_thickness_that_is_not_positive_is_refused_by_name(t):
    d = protocol_to_dict(Protocol(BOX, (Shell(TOP, 2.0),)))
    d["operations"][0]["t"] = t
    with pytest.raises(ProtocolError, match=r"operations\[0\]\.t"):
        loads(json.dumps(d))


def test_the_shell_hollows_the_box_open_at_f():
    solid = apply_operation(make_box(BOX), Shell(TOP, 2.0))
    assert solid.isValid()
    assert solid.Volume() == pytest.approx(40 * 30 * 20 - 36 * 26 * 18, rel=1e-9)
    assert "shell" in Shell(TOP, 2.0).describe().lower()


@pytest.mark.parametrize(
    "t, why",
    [(15.0, "fails on this solid"), (16.0, "more than the solid allows"), (40.0, "more than")],
)
def test_a_thickness_the_solid_cannot_take_names_the_step_and_t(t, why):
    box = make_box(BOX)
    before = box.Volume()
    with pytest.raises(OperationError, match=rf"step 1 \(shell\): .*t = {t:g} mm.*{why}"):
        replay(Protocol(BOX, (Shell(TOP, t),)))
    with pytest.raises(OperationError):
        apply_operation(box, Shell(TOP, t))
    assert box.Volume() == before


@pytest.mark.parametrize(
    "feature",
    [
        Sweep(TOP, (0, 0, 10), 6, 4, 8, straight_profile(6, 4, 8), Mode.ADD),
        Sweep(TOP, (0, 0, 10), 5, 5, 8, straight_profile(5, 5, 8), Mode.SUBTRACT),
    ],
    ids=["cone", "hole"],
)
def test_the_walls_follow_cones_and_cylinders(feature):
    solid = apply_operation(make_box(BOX), feature)
    shelled = apply_operation(solid, Shell(BOTTOM, 1.0))
    assert shelled.isValid()
    assert 0 < shelled.Volume() < solid.Volume()


@pytest.mark.parametrize(
    "feature, kind",
    [
        (
            Bevel(
                TOP,
                (20, 15, 10),
                (20, 15, -10),
                ((12, 15, 10), (16.4, 15, 10), (20, 11.4, 10), (20, 6, 10)),
            ),
            "extrusion",
        ),
        (Sweep(TOP, (0, 0, 10), 6, 4, 8, ((8, 3), (5, 6)), Mode.ADD), "revolution"),
    ],
    ids=["bevel", "curved sweep"],
)
def test_faces_the_offset_cannot_follow_are_refused_by_kind(feature, kind):
    solid = apply_operation(make_box(BOX), feature)
    with pytest.raises(OperationError, match=rf"cannot follow the solid's {kind} faces"):
        apply_operation(solid, Shell(BOTTOM, 1.0))


def test_a_cylinder_opened_at_its_top_is_a_cup():
    cylinder = apply_operation(
        make_box(BOX),
        Sweep(TOP, (0, 0, 10), 12, 12, 20, straight_profile(12, 12, 20), Mode.REPLACE),
    )
    cup = apply_operation(cylinder, Shell(FaceRef((0.0, 0.0, 30.0), (0.0, 0.0, 1.0)), 2.0))
    assert cup.Volume() == pytest.approx(math.pi * (12**2 * 20 - 10**2 * 18), rel=1e-6)
