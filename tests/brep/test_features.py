# SPDX-License-Identifier: LGPL-2.1-or-later
"""Each step as a native feature's plan (brep/features): its outline and extrusion or
revolution rebuild the core's solid; its outline's coordinates are its named dimensions."""

import dataclasses
from pathlib import Path

import pytest
from round_fixtures import round_protocols

from Sketch2CADWorkbench.brep.features import (
    Kind,
    apply_feature,
    combined,
    feature_tool,
    mismatch,
    plan_protocol,
)
from Sketch2CADWorkbench.brep.protocol import Sweep, load

ROOT = Path(__file__).resolve().parents[2]
TOL = 1e-6


@pytest.fixture(scope="module", params=["bolt", "lamp", "pipe"])
def plan(request):
    return plan_protocol(load(ROOT / "examples" / "protocols" / f"{request.param}.json"))


def test_each_feature_rebuilds_the_cores_solid_of_its_step(plan):
    for feature in plan.features[1:]:
        before, after = plan.solids[feature.step - 1], plan.solids[feature.step]
        got = combined(before, feature_tool(feature, before), feature.mode)
        assert mismatch(got, after) <= TOL, feature.step


def test_a_changed_dimension_changes_the_solid(plan):
    feature = next(f for f in plan.features if f.kind is Kind.REVOLVE)
    before, after = plan.solids[feature.step - 1], plan.solids[feature.step]
    half = dataclasses.replace(feature, angle=feature.angle / 2)
    assert mismatch(combined(before, feature_tool(half, before), feature.mode), after) > TOL


def test_a_sweeps_outline_holds_its_parameters_by_name(plan):
    for feature, op in zip(plan.features[1:], plan.protocol.operations, strict=False):
        if not isinstance(op, Sweep):
            continue
        dims = feature.outline.dims
        assert (dims["r0"], dims["r1"], dims["d"]) == (op.r0, op.r1, op.d)
        for name in ("cp1", "cp2"):
            if f"{name}_r" in dims:  # a curved profile (a straight one is a line)
                k = int(name[-1]) - 1
                assert (dims[f"{name}_r"], dims[f"{name}_h"]) == pytest.approx(op.profile[k])


def test_rounds_plan_as_fillets_chamfers_and_profiles_that_rebuild_the_core():
    kinds = set()
    for name, protocol in round_protocols().items():
        plan = plan_protocol(protocol)
        for feature in plan.features[1:]:
            got = apply_feature(feature, plan.solids[feature.step - 1])
            assert mismatch(got, plan.solids[feature.step]) <= TOL, (name, feature.step)
            kinds.add(feature.kind)
    assert {Kind.FILLET, Kind.CHAMFER, Kind.EXTRUDE, Kind.REVOLVE} <= kinds


def test_a_fillets_radius_is_its_dimension():
    plan = plan_protocol(round_protocols()["rim fillet"])
    fillet = plan.features[-1]
    assert fillet.kind is Kind.FILLET and fillet.dims == {"radius": 3.0}
    wider = dataclasses.replace(fillet, dims={"radius": 4.0})
    assert mismatch(apply_feature(wider, plan.solids[-2]), plan.solids[-1]) > TOL
