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


def test_a_head_of_the_unets_four_classes_answers_with_four(net, tmp_path):
    # a head trained before the shell was a class (the layout of its class layer says
    # so) loads and classifies the four; interpret then proposes the shell by geometry
    from Sketch2CADWorkbench.inference.head.checkpoint import load_head, save_head

    face_id, strokes = scene()
    four = StructureHead(HeadConfig(channels=feature_channels(net), width=16, layers=1, classes=4))
    save_head(tmp_path / "h.pt", four)
    raw = torch.load(tmp_path / "h.pt", weights_only=False)
    del raw["config"]["classes"]  # as an earlier version wrote it
    torch.save(raw, tmp_path / "h.pt")
    head, _ = load_head(tmp_path / "h.pt")
    assert head.config.classes == 4 and four.state_dict().keys() == head.state_dict().keys()
    p = StructuredPredictor(net, head, threads=1)
    x = np.random.default_rng(1).random((5, SIZE, SIZE)).astype(np.float32)
    p.observe(strokes, face_id)
    assert p.classify(x).shape == (len(CLASSES),)
