# SPDX-License-Identifier: LGPL-2.1-or-later
"""Rounds across an edge (`--round-share`): on rims and straight edges, with their
chains and outlines, each one that builds; a share of 0 draws what it drew before."""

import numpy as np
from round_fixtures import BASE, KNOB

from datagen.generate import Context, sample_on
from datagen.operations import PlanarFace
from datagen.rounds import sample_round
from datagen.sequences import Sequence, Stage, sample_operation
from Sketch2CADWorkbench.brep.faces import OperationError, planar_faces
from Sketch2CADWorkbench.brep.operators import build, operation_result
from Sketch2CADWorkbench.brep.protocol import EdgeSet, OperatorType, Protocol
from Sketch2CADWorkbench.render.maps import MapRenderer
from Sketch2CADWorkbench.sketch.labels import BEVEL_L, BEVEL_L_PRIME


def knob_stage() -> Stage:
    return Stage(build(Protocol(BASE, (KNOB,))))


def test_rounds_on_a_knob_take_its_rims_and_edges_with_every_edge_set_and_build():
    stage = knob_stage()
    rng = np.random.default_rng(4)
    kinds, sets, rims, built, drawn = set(), set(), 0, 0, 0
    for face, normal, _ in planar_faces(stage.solid):
        f = PlanarFace(face, normal)
        for _ in range(12):
            op = sample_round(rng, stage.solid, f)
            if op is None:
                continue
            assert op.across and (op.edges is EdgeSet.DRAWN or op.regular)
            kinds.add("fillet" if op.radius else "chamfer" if op.distances else "freeform")
            sets.add(op.edges)
            x, y, _ = op.corner
            rims += abs(np.hypot(x, y) - 15.0) < 1e-6
            drawn += 1
            try:  # OCCT refuses some (too large for a face beside the edge): drawn again
                operation_result(stage.solid, op)
                built += 1
            except OperationError:
                pass
    assert built >= drawn / 2
    assert kinds == {"fillet", "chamfer", "freeform"} and sets == set(EdgeSet)
    assert rims > 0


def test_a_round_share_of_0_draws_the_operations_it_drew_before():
    stage = knob_stage()
    a = sample_operation(np.random.default_rng(3), stage, OperatorType.BEVEL)
    b = sample_operation(np.random.default_rng(3), stage, OperatorType.BEVEL, round_share=0.0)
    assert a.op == b.op and not a.op.across
    c = sample_operation(np.random.default_rng(3), stage, OperatorType.BEVEL, round_share=1.0)
    assert c.op.across


def test_a_round_sample_labels_l_and_l_prime_in_a_view_facing_the_profile():
    context = Context(
        Sequence(Protocol(BASE, (KNOB,)), [Stage(build(Protocol(BASE, ()))), knob_stage()])
    )
    sample = sample_on(
        context,
        np.random.default_rng(2),
        1,
        MapRenderer(),
        kind=OperatorType.BEVEL,
        round_share=1.0,
    )
    assert sample.operation.across
    assert sorted(sample.stroke_parts) == [BEVEL_L_PRIME, BEVEL_L]
    direction = np.asarray(sample.camera.direction, float)
    assert abs(direction[2]) < 0.95  # looking from the side, not straight down
