# SPDX-License-Identifier: LGPL-2.1-or-later
"""The structured predictor the interpret pipeline calls."""

import numpy as np
import torch
from head_fixtures import SIZE, scene

from Sketch2CADWorkbench.inference.head.decode import decode_roles
from Sketch2CADWorkbench.inference.head.model import ROLES, HeadConfig, StructureHead
from Sketch2CADWorkbench.inference.head.paint import paint_curve
from Sketch2CADWorkbench.inference.head.predictor import StructuredPredictor
from Sketch2CADWorkbench.inference.head.tokens import feature_channels
from Sketch2CADWorkbench.sketch.labels import CLASSES, LABELLED


def test_predictor_answers_as_the_unet_until_it_observes_a_sketch(net, tmp_path):
    face_id, strokes = scene()
    head = StructureHead(HeadConfig(channels=feature_channels(net), width=16, layers=1))
    p = StructuredPredictor(net, head, threads=1)
    x = np.random.default_rng(0).random((5, SIZE, SIZE)).astype(np.float32)
    unet = net.predict(torch.from_numpy(x)[None])
    assert np.allclose(p.classify(x), unet[0][0].numpy(), atol=1e-6)
    p.observe(strokes, face_id)
    x2 = x.copy()
    probs = p.classify(x2)
    assert probs.shape == (len(LABELLED),) and abs(probs.sum() - 1) < 1e-5
    for op in LABELLED:  # the shell's roles and face too, which the U-Net has no maps for
        f, c = p.segment(x2, op)
        roles = p.stroke_roles(x2, op)
        assert roles.shape == (3, ROLES[LABELLED.index(op)])
        assert np.array_equal(
            c, paint_curve(strokes, decode_roles(torch.from_numpy(roles), LABELLED.index(op)), SIZE)
        )
        faces = p.face_probabilities(x2, op)
        assert set(faces) == {3, 7} and abs(sum(faces.values()) - 1) < 1e-5
        best = max(faces, key=faces.get)
        assert np.array_equal(f > 0.5, face_id == best)
    x3 = x2.copy()  # inputs of a sketch it did not observe: never read with stale strokes
    assert np.allclose(p.segment(x3, CLASSES[0])[1], unet[2][0, 0].numpy(), atol=1e-6)
