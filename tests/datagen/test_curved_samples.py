# SPDX-License-Identifier: LGPL-2.1-or-later
"""Samples on curved faces (#16): the last operation stands on a cylinder's or cone's side
of its context, builds there, and its labels name that face and the stroke parts; the
bound that rejects candidates before their Booleans holds."""
import numpy as np

from datagen.curved import (
    change_bound_on_curved,
    curved_context,
    curved_sample,
    draw_kind,
    sample_on_curved,
)
from datagen.generate import sample_rng
from datagen.operations import straight_profile
from Sketch2CADWorkbench.brep.faces import OperationError, is_curved, model_scale
from Sketch2CADWorkbench.brep.operators import apply_operation, operation_result, replay
from Sketch2CADWorkbench.brep.protocol import Mode, OperatorType


def test_a_curved_sample_stands_on_a_curved_face_of_its_context(renderer):
    s = curved_sample(sample_rng(5, 0), 1, renderer)  # a hole drilled into a cylinder
    assert s.operation.face.surface.curved
    context = replay(s.context)[-1]
    faces = context.Faces()
    labelled = np.unique(s.face_id[s.face_label > 0.5])
    assert len(labelled) == 1
    assert faces[int(labelled[0])].geomType() in ("CYLINDER", "CONE")
    assert set(s.stroke_parts) == {0, 1, 2}
    assert abs(apply_operation(context, s.operation).Volume() - context.Volume()) > 0


def test_the_cheap_bound_is_never_below_the_volume_change_a_candidate_makes():
    # it rejects candidates before their Booleans: one it underestimated would be lost
    rng = np.random.default_rng(3)
    checked = set()
    for _ in range(3):
        seq, faces = curved_context(rng)
        solid = seq.stages[-1].solid
        for _ in range(12):
            got = sample_on_curved(rng, faces[int(rng.integers(len(faces)))], draw_kind(rng))
            if got is None:
                continue
            op, f = got
            try:
                change = abs(operation_result(solid, op).volume - seq.stages[-1].volume)
            except OperationError:
                continue
            # up to the noise of OCCT's volumes of a large solid (~1e-5 of it), far
            # under the 1% a kept candidate changes
            noise = 1e-4 * seq.stages[-1].volume
            assert change <= change_bound_on_curved(op, f, model_scale(solid)) + noise
            checked.add(op.type)
    assert checked == {OperatorType.ADDSUB, OperatorType.SWEEP, OperatorType.EXTRUDE}


def test_a_curved_context_ends_in_an_added_cylinder_or_cone():
    for seed in range(3):
        seq, faces = curved_context(np.random.default_rng(seed))
        op = seq.protocol.operations[-1]
        assert op.type is OperatorType.SWEEP and op.mode is Mode.ADD
        assert np.allclose(op.profile, straight_profile(op.r0, op.r1, op.d))
        assert faces and all(is_curved(f) for f in faces)
