# SPDX-License-Identifier: LGPL-2.1-or-later
"""Any sequence of in-range parameters ends in one valid solid or an OperationError, the
same whether the base face is resolved or handed in, and the same replayed as a protocol
as applied step by step."""

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from Sketch2CADWorkbench.brep.exchange import to_brep_text
from Sketch2CADWorkbench.brep.faces import OperationError, face_ref_of, planar_faces
from Sketch2CADWorkbench.brep.geometry import plane_basis
from Sketch2CADWorkbench.brep.operators import (
    apply_operation,
    build,
    make_box,
    operation_result,
    replay,
)
from Sketch2CADWorkbench.brep.protocol import (
    AddSubPrism,
    Bevel,
    Box,
    Extrude,
    Mode,
    Protocol,
    Sweep,
)

unit = st.floats(0.0, 1.0)


@st.composite
def operation_on(draw, solid):
    """Any operation whose parameters lie in their documented ranges (not necessarily sensible)."""
    faces = planar_faces(solid)
    face, n, _ = faces[draw(st.integers(0, len(faces) - 1))]
    ref = face_ref_of(face)
    p = np.array(ref.point)
    u, v = plane_basis(n)
    size = solid.BoundingBox().DiagonalLength
    kind = draw(st.sampled_from(["extrude", "bevel", "addsub", "sweep"]))
    if kind == "extrude":
        d = draw(st.floats(-0.6, 0.6).filter(lambda x: abs(x) > 0.01)) * size
        return Extrude(ref, d)
    if kind == "addsub":
        k = draw(st.integers(3, 6))
        r = draw(st.floats(0.02, 0.4)) * size
        angles = sorted(draw(st.lists(st.floats(0, 2 * math.pi), min_size=k, max_size=k)))
        poly = tuple(tuple(p + r * (math.cos(a) * u + math.sin(a) * v)) for a in angles)
        mode = draw(st.sampled_from(list(Mode)))
        return AddSubPrism(ref, poly, draw(st.floats(0.01, 0.5)) * size, mode)
    if kind == "sweep":
        r0, r1 = (draw(st.floats(0.01, 0.3)) * size for _ in range(2))
        d = draw(st.floats(0.01, 0.5)) * size
        inner = tuple((draw(st.floats(0.0, 0.4)) * size, draw(unit) * d) for _ in range(2))
        center = tuple(p + draw(st.floats(-0.2, 0.2)) * size * u)
        return Sweep(ref, center, r0, r1, d, inner, draw(st.sampled_from(list(Mode))))
    # bevel: at one of f's vertices, crease into the solid by the model size
    verts = face.Vertices()
    c = np.array(verts[draw(st.integers(0, len(verts) - 1))].toTuple())
    a = c + draw(st.floats(0.01, 0.3)) * size * u
    b = c + draw(st.floats(0.01, 0.3)) * size * v
    ctrl = (tuple(a), tuple(a + draw(unit) * (c - a)), tuple(b + draw(unit) * (c - b)), tuple(b))
    return Bevel(ref, tuple(c), tuple(c - n * draw(st.floats(0.05, 1.0)) * size), ctrl)


@settings(max_examples=60, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.data(), st.tuples(*[st.floats(5.0, 80.0)] * 3), st.integers(1, 3))
def test_random_sequence_ends_in_a_valid_solid_or_an_operation_error(data, size, length):
    solid = make_box(Box(size))
    for _ in range(length):
        op = data.draw(operation_on(solid))
        before = solid.Volume()
        try:
            result = apply_operation(solid, op)
        except OperationError as e:
            assert str(e)  # the reason is stated
            assert solid.Volume() == before and solid.isValid()  # input untouched
            return
        assert len(result.Solids()) == 1 and result.isValid() and result.Volume() > 0
        solid = result


@settings(max_examples=40, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.data(), st.tuples(*[st.floats(5.0, 80.0)] * 3), st.integers(1, 3))
def test_an_operation_given_its_base_face_builds_what_resolving_the_face_builds(data, size, length):
    """Data generation hands apply_operation the face it drew op.face from: the result,
    or the error, is the one resolving op.face gives."""
    solid = make_box(Box(size))
    for _ in range(length):
        op = data.draw(operation_on(solid))
        (face,) = [f for f, _, _ in planar_faces(solid) if face_ref_of(f) == op.face]
        try:
            resolved = operation_result(solid, op)
        except OperationError as e:
            with pytest.raises(OperationError) as held_error:
                operation_result(solid, op, face)
            assert str(held_error.value) == str(e)
            return
        held = operation_result(solid, op, face)
        assert to_brep_text(held.solid) == to_brep_text(resolved.solid)
        assert held.volume == resolved.volume == resolved.solid.Volume()
        solid = resolved.solid


@settings(max_examples=40, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.data(), st.tuples(*[st.floats(5.0, 80.0)] * 3), st.integers(1, 4))
def test_a_protocol_replays_to_what_its_steps_applied_one_by_one_build(data, size, length):
    """replay and build check OCCT's validity once, at the end, and build again with
    every check where that fails: the solids, or the error naming the step, are the ones
    applying each operation in turn, each checked, gives."""
    solids, ops, error = [make_box(Box(size))], [], None
    for i in range(1, length + 1):
        ops.append(data.draw(operation_on(solids[-1])))
        try:
            solids.append(apply_operation(solids[-1], ops[-1]))
        except OperationError as e:
            error = f"step {i} ({ops[-1].type.value}): {e}"
            break
    protocol = Protocol(Box(size), tuple(ops))
    if error is not None:
        for run in (replay, build):
            with pytest.raises(OperationError) as raised:
                run(protocol)
            assert str(raised.value) == error
        return
    texts = [to_brep_text(s) for s in solids]
    assert [to_brep_text(s) for s in replay(protocol)] == texts
    assert to_brep_text(build(protocol)) == texts[-1]
