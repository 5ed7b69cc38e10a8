# SPDX-License-Identifier: LGPL-2.1-or-later
"""Samples on curved faces (#16): the last operation stands on a cylinder's or cone's side
of its context, builds there, and its labels name that face and the stroke parts."""
import numpy as np

from datagen.curved import curved_sample
from datagen.generate import sample_rng
from Sketch2CADWorkbench.brep.operators import apply_operation, replay


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
