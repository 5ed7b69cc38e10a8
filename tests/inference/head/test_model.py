# SPDX-License-Identifier: LGPL-2.1-or-later
"""The structured head: its logits, batching, and the attention biases."""

import torch
from head_fixtures import SIZE, scene, scene_tokens

from Sketch2CADWorkbench.inference.head.model import (
    N_CLASSES,
    ROLES,
    HeadConfig,
    StructureHead,
    collate,
)
from Sketch2CADWorkbench.inference.head.tokens import feature_channels
from Sketch2CADWorkbench.inference.models import N_OPS


def test_the_head_gives_logits_per_stroke_and_face_with_padding_masked(net):
    face_id, strokes = scene()
    a = scene_tokens(net, strokes, face_id)
    b = scene_tokens(net, strokes[:1], face_id[:, :16].repeat(2, 1).reshape(SIZE, SIZE))
    head = StructureHead(HeadConfig(channels=feature_channels(net), width=16, layers=1)).eval()
    cls, roles, faces = head(*collate([a, b]))
    assert cls.shape == (2, N_CLASSES) and roles.shape == (2, 3, sum(ROLES))
    assert faces.shape[-1] == N_CLASSES
    assert torch.isinf(faces[1, len(b.face) :]).all() and torch.isfinite(faces[0]).all()


def test_an_untrained_head_classifies_as_the_unet_with_the_shell_at_zero(net):
    # the class logits are the U-Net's plus a correction that starts at zero; the shell,
    # which the U-Net has no logit for, starts at zero too
    face_id, strokes = scene()
    t = scene_tokens(net, strokes, face_id)
    head = StructureHead(HeadConfig(channels=feature_channels(net), width=16, layers=1)).eval()
    with torch.no_grad():
        cls, _, _ = head(*collate([t]))
    assert torch.allclose(cls[0, :N_OPS], t.cls[:N_OPS]) and float(cls[0, N_OPS]) == 0.0


def test_the_head_reads_a_batch_alike_in_training_and_in_inference(net):
    face_id, strokes = scene()
    batch = collate([scene_tokens(net, strokes, face_id), scene_tokens(net, strokes[1:], face_id)])
    head = StructureHead(
        HeadConfig(channels=feature_channels(net), width=16, layers=2, dropout=0.0)
    )
    with torch.no_grad():
        head.end_bias.weight.normal_()
        head.face_bias.weight.normal_()
        trained = head.train()(*batch)
    with torch.inference_mode():
        inferred = head.eval()(*batch)
    for a, b in zip(trained, inferred, strict=True):
        assert torch.allclose(a, b, atol=1e-5)


def test_a_head_without_context_layers_reads_each_token_alone(net):
    face_id, strokes = scene()
    t = scene_tokens(net, strokes, face_id)
    head = StructureHead(HeadConfig(channels=feature_channels(net), width=16, layers=0)).eval()
    _, alone, _ = head(*collate([t]))
    t.stroke[1:] = torch.randn_like(t.stroke[1:])  # the other strokes change
    _, again, _ = head(*collate([t]))
    assert torch.allclose(alone[0, 0], again[0, 0], atol=1e-6)
    assert not torch.allclose(alone[0, 1], again[0, 1])


def test_strokes_whose_ends_meet_attend_to_each_other_by_the_end_bias(net):
    face_id, strokes = scene()  # strokes 0 and 1 share an end; stroke 2 lies apart
    a = scene_tokens(net, strokes, face_id)
    b = scene_tokens(net, strokes[:1], face_id)
    head = StructureHead(HeadConfig(channels=feature_channels(net), width=16, layers=1))
    with torch.no_grad():
        head.end_bias.weight.copy_(torch.arange(6.0)[:, None].repeat(1, 4))
        _cls, stroke, s_mask, _face, f_mask, on_face = collate([a, b])
        pad = torch.cat([torch.zeros(2, 1, dtype=torch.bool), ~s_mask, ~f_mask], 1)
        bias = head._attention_bias(stroke, on_face, pad)
    strokes_block = bias[0, 0, 1:4, 1:4]
    assert strokes_block[0, 1] == strokes_block[1, 0] == 0  # touching: the first bin
    assert strokes_block[0, 2] == 5  # farther than the last bin edge
    assert torch.isinf(bias[1, :, :, 2:4]).all()  # padded strokes are never attended to
    assert bias[1, :, :2, 1].eq(0).all()


def test_a_stroke_and_the_face_it_lies_on_attend_to_each_other_by_the_face_bias(net):
    face_id, strokes = scene()  # stroke 0 lies on face 3, stroke 2 on face 7
    t = scene_tokens(net, strokes, face_id)
    on = dict(zip(t.face_ids.tolist(), t.on_face.T, strict=False))
    assert on[3][0] == 1 and on[7][0] == 0 and on[7][2] == 1 and on[3][2] == 0
    head = StructureHead(HeadConfig(channels=feature_channels(net), width=16, layers=1))
    with torch.no_grad():
        head.face_bias.weight.copy_(torch.arange(5.0)[:, None].repeat(1, 8))
        head.face_bias.weight[:, 4:] += 10  # face-to-stroke apart from stroke-to-face
        _cls, stroke, s_mask, _face, f_mask, on_face = collate([t])
        pad = torch.cat([torch.zeros(1, 1, dtype=torch.bool), ~s_mask, ~f_mask], 1)
        bias = head._attention_bias(stroke, on_face, pad)[0, 0]
    three = 4 + t.face_ids.tolist().index(3)  # its token: after cls and 3 strokes
    assert bias[1, three] == 4 and bias[3, three] == 0  # stroke 0 -> face 3: all; 2: none
    assert bias[three, 1] == 14 and bias[three, 3] == 10
