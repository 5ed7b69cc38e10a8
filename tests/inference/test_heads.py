# SPDX-License-Identifier: LGPL-2.1-or-later
"""Structured heads: tokens per stroke and per face, decoding, painting back into F and C,
the predictor the interpret pipeline can call, and the head's checkpoints."""

import numpy as np
import pytest
import torch
import torch.nn.functional as F
from drawing_fixtures import prism_drawing

from datagen.strokes import stroke_maps
from Sketch2CADWorkbench.brep.protocol import OperatorType
from Sketch2CADWorkbench.inference.heads import (
    POINTS,
    ROLES,
    STROKE_GEOMETRY,
    HeadConfig,
    StructuredPredictor,
    StructureHead,
    _Polylines,
    choose,
    collate,
    count_fits,
    decode_roles,
    feature_channels,
    feature_maps,
    load_head,
    load_structured_predictor,
    paint_curve,
    paint_face,
    role_probabilities,
    save_head,
    stroke_geometry,
    tokens,
)
from Sketch2CADWorkbench.inference.models import ModelConfig, Sketch2CADNet, save_checkpoint
from Sketch2CADWorkbench.sketch.labels import BEVEL_L, BEVEL_L_PRIME, CLASSES, END, PROFILE, START

SIZE = 32


def _scene():
    """Two faces side by side (IDs 3 and 7), three strokes, random-weights maps."""
    face_id = np.full((SIZE, SIZE), -1, np.int16)
    face_id[4:28, 4:16] = 3
    face_id[4:28, 16:28] = 7
    strokes = [
        np.array([[6.0, 8.0], [14.0, 8.0]]),
        np.array([[6.0, 8.0], [6.0, 24.0]]),
        np.array([[20.0, 10.0], [26.0, 20.0], [21.0, 25.0]]),
    ]
    return face_id, strokes


@pytest.fixture
def net(tiny_config):
    torch.manual_seed(0)
    return Sketch2CADNet(tiny_config).eval()


def _tokens(net, strokes, face_id):
    x = torch.rand(1, 5, SIZE, SIZE, generator=torch.Generator().manual_seed(1))
    with torch.no_grad():
        u = feature_maps(net, x)
    return tokens(u.logits[0], u.sketch(0), strokes, face_id)


def test_one_token_per_stroke_and_per_visible_face(net):
    face_id, strokes = _scene()
    t = _tokens(net, strokes, face_id)
    c = feature_channels(net)
    assert t.stroke.shape == (3, 2 * c + STROKE_GEOMETRY)
    assert sorted(t.face_ids.tolist()) == [3, 7]
    assert t.face.shape[0] == 2 and torch.isfinite(t.face).all() and torch.isfinite(t.stroke).all()


def test_a_face_token_holds_its_area_centroid_and_spread(net):
    face_id, strokes = _scene()
    t = _tokens(net, strokes, face_id)
    c = feature_channels(net)
    for fid, token in zip(t.face_ids.tolist(), t.face, strict=False):
        ys, xs = np.nonzero(face_id == fid)
        geo = token[c : c + 5].numpy()
        assert np.allclose(
            geo,
            [
                len(xs) / SIZE**2,
                xs.mean() / SIZE,
                ys.mean() / SIZE,
                xs.std() / SIZE,
                ys.std() / SIZE,
            ],
            atol=1e-6,
        )


def test_a_face_token_counts_the_unets_f_votes_on_it(net):
    face_id, strokes = _scene()
    x = torch.rand(1, 5, SIZE, SIZE, generator=torch.Generator().manual_seed(1))
    with torch.no_grad():
        u = feature_maps(net, x)
    t = tokens(u.logits[0], u.sketch(0), strokes, face_id)
    votes = net.upsample(u.f)[0].numpy() > 0  # (4, S, S): where each operator's F says f
    c = feature_channels(net)
    for fid, token in zip(t.face_ids.tolist(), t.face, strict=False):
        on = face_id == fid
        share = votes[:, on].sum(1) / on.sum()
        assert np.allclose(token[c + 5 : c + 5 + len(CLASSES)].numpy(), share, atol=1e-6)


def test_a_face_token_holds_its_normal_as_seen_in_the_image(net):
    # face 3 tilts its normal to the right and up the image, face 7 left and down
    face_id, strokes = _scene()
    x = torch.ones(1, 5, SIZE, SIZE)
    x[0, 2][torch.from_numpy(face_id == 3)], x[0, 3][torch.from_numpy(face_id == 3)] = 1.5, 1.3
    x[0, 2][torch.from_numpy(face_id == 7)], x[0, 3][torch.from_numpy(face_id == 7)] = 0.6, 0.8
    with torch.no_grad():
        u = feature_maps(net, x)
    t = tokens(u.logits[0], u.sketch(0), strokes, face_id)
    seen = dict(zip(t.face_ids.tolist(), t.normal_image.numpy(), strict=False))
    assert np.allclose(seen[3], [0.5, -0.3], atol=0.02)  # camera y up is image y down
    assert np.allclose(seen[7], [-0.4, 0.2], atol=0.02)


def test_tokens_read_the_unets_maps_as_if_upsampled_to_its_internal_size():
    # the tokens never upsample the coarser decoder maps (factors 4, 2 and 1 here): they
    # must read what pooling F.interpolate's upsampled maps would
    torch.manual_seed(4)
    net = Sketch2CADNet(
        ModelConfig(
            image_size=SIZE, internal_size=SIZE // 2, widths=(4, 6, 8, 8), classifier_hidden=8
        )
    ).eval()
    face_id, strokes = _scene()
    face_id[face_id < 0] = 9  # a face along the border, where the upsampling clamps
    x = torch.rand(1, 5, SIZE, SIZE, generator=torch.Generator().manual_seed(5))
    with torch.no_grad():
        u = feature_maps(net, x)
        t = tokens(u.logits[0], u.sketch(0), strokes, face_id)
        i = SIZE // 2
        assert sorted({m.shape[-1] for m in u.maps}) == [i // 4, i // 2, i]
        up = torch.cat(
            [F.interpolate(m, size=(i, i), mode="bilinear", align_corners=False) for m in u.maps], 1
        )[0]  # (C, I, I)
        c = up.shape[0]
        ys, xs = np.divmod(np.arange(SIZE * SIZE), SIZE)
        cells = up[:, ys * i // SIZE, xs * i // SIZE]  # each full-size pixel's cell
        for fid, token in zip(t.face_ids.tolist(), t.face, strict=False):
            on = torch.from_numpy(face_id.ravel() == fid)
            assert torch.allclose(token[:c], cells[:, on].mean(1), atol=1e-5)
        pts = _Polylines.of(strokes).resample(POINTS)
        grid = torch.from_numpy((2 * pts / SIZE - 1).astype(np.float32))[None]
        at = F.grid_sample(
            up[None], grid, mode="bilinear", padding_mode="border", align_corners=False
        )[0]  # (C, S, P)
        assert torch.allclose(t.stroke[:, :c], at.mean(2).T, atol=1e-5)
        assert torch.allclose(t.stroke[:, c : 2 * c], at.amax(2).T, atol=1e-5)


def test_a_stroke_token_holds_its_centroid_ends_chord_and_arc():
    strokes = [
        np.array([[4.0, 8.0], [4.0, 0.0], [0.0, 0.0]]),  # drawn right to left
        np.array([[16.0, 16.0]]),
    ]  # a dot
    geo = stroke_geometry(strokes, np.array([[0.0, 1.0], [0.0, 0.0]]), SIZE)
    assert geo.shape == (2, 14)
    px = geo[:, :10] * SIZE  # centroid, ends, (cos 2a, sin 2a), chord, arc; in pixels
    assert np.allclose(px[0, :2], [8 / 3, 8 / 3])
    assert np.allclose(px[0, 2:6], [0, 0, 4, 8])  # the ends, smaller x first
    assert np.allclose(px[0, 8:10], [np.hypot(4, 8), 12])
    assert np.isclose(geo[0, 10], np.hypot(4, 8) / 12)  # closedness: chord / arc
    assert np.isclose(geo[0, 11], (8 * 4 / np.hypot(4, 8)) / 12)  # corner off the chord / arc
    assert np.isclose(geo[0, 12], 8 / np.hypot(4, 8))  # |cos| of the chord to the normal
    assert np.allclose(px[1, :6], 16) and px[1, 9] == 0
    assert np.isfinite(geo).all()


def test_a_stroke_reads_the_same_drawn_either_way(net):
    face_id, strokes = _scene()
    forward = _tokens(net, strokes, face_id)
    backward = _tokens(net, [s[::-1] for s in strokes], face_id)
    assert torch.allclose(forward.stroke, backward.stroke, atol=1e-5)
    normal = np.array([[0.3, 0.4]] * len(strokes))
    assert np.allclose(
        stroke_geometry(strokes, normal, SIZE),
        stroke_geometry([s[::-1] for s in strokes], normal, SIZE),
        atol=1e-6,
    )


def test_a_sketch_without_faces_in_view_still_gives_stroke_tokens(net):
    _, strokes = _scene()
    t = _tokens(net, strokes, np.full((SIZE, SIZE), -1, np.int16))
    assert t.stroke.shape[0] == 3 and t.face.shape[0] == 0


def test_the_head_gives_logits_per_stroke_and_face_with_padding_masked(net):
    face_id, strokes = _scene()
    a = _tokens(net, strokes, face_id)
    b = _tokens(net, strokes[:1], face_id[:, :16].repeat(2, 1).reshape(SIZE, SIZE))
    head = StructureHead(HeadConfig(channels=feature_channels(net), width=16, layers=1)).eval()
    cls, roles, faces = head(*collate([a, b]))
    assert cls.shape == (2, 4) and roles.shape == (2, 3, sum(ROLES))
    assert torch.isinf(faces[1, len(b.face) :]).all() and torch.isfinite(faces[0]).all()


def test_the_head_reads_a_batch_alike_in_training_and_in_inference(net):
    face_id, strokes = _scene()
    batch = collate([_tokens(net, strokes, face_id), _tokens(net, strokes[1:], face_id)])
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
    face_id, strokes = _scene()
    t = _tokens(net, strokes, face_id)
    head = StructureHead(HeadConfig(channels=feature_channels(net), width=16, layers=0)).eval()
    _, alone, _ = head(*collate([t]))
    t.stroke[1:] = torch.randn_like(t.stroke[1:])  # the other strokes change
    _, again, _ = head(*collate([t]))
    assert torch.allclose(alone[0, 0], again[0, 0], atol=1e-6)
    assert not torch.allclose(alone[0, 1], again[0, 1])


def test_a_bevel_gets_exactly_one_profile_l():
    bevel = CLASSES.index(OperatorType.BEVEL)
    both_l = torch.tensor([[0.2, 0.8], [0.3, 0.7]])
    assert decode_roles(both_l[:, [1, 0]] if BEVEL_L == 0 else both_l, bevel).count(BEVEL_L) == 1
    neither = torch.tensor([[0.9, 0.1], [0.6, 0.4]])
    labels = decode_roles(neither if BEVEL_L == 1 else neither[:, [1, 0]], bevel)
    assert labels.count(BEVEL_L) == 1 and labels[1] == BEVEL_L


def test_a_prism_gets_n_start_n_profile_n_end_strokes():
    # the head reads the far outline of a 3-sided prism half as start: the counts fix it
    probs = torch.tensor(
        [[0.9, 0.05, 0.05]] * 3
        + [[0.1, 0.8, 0.1]] * 3
        + [[0.6, 0.0, 0.4], [0.55, 0.0, 0.45], [0.2, 0.0, 0.8]]
    )
    addsub = CLASSES.index(OperatorType.ADDSUB)
    assert [int(v) for v in probs.argmax(1)].count(START) == 5
    assert decode_roles(probs, addsub) == [START] * 3 + [PROFILE] * 3 + [END] * 3


def test_a_sweep_gets_one_start_two_profiles_one_end():
    probs = torch.tensor([[0.7, 0.2, 0.1], [0.1, 0.8, 0.1], [0.2, 0.7, 0.1], [0.6, 0.1, 0.3]])
    assert decode_roles(probs, CLASSES.index(OperatorType.SWEEP)) == [START, PROFILE, PROFILE, END]


def test_counts_no_drawing_has_keep_each_strokes_likeliest_role():
    probs = torch.tensor([[0.9, 0.05, 0.05]] * 4 + [[0.1, 0.1, 0.8]])
    for op in (OperatorType.ADDSUB, OperatorType.SWEEP):  # 5 strokes: neither 3n nor 4
        assert decode_roles(probs, CLASSES.index(op)) == [START] * 4 + [END]
    extrude = torch.tensor([[0.9, 0.1]] * 4)
    assert decode_roles(extrude, CLASSES.index(OperatorType.EXTRUDE)) == [0] * 4


def test_the_class_token_says_which_drawings_have_that_many_strokes(net):
    fits = dict(
        zip(CLASSES, zip(count_fits(2), count_fits(4), count_fits(9), strict=False), strict=False)
    )
    assert fits[OperatorType.EXTRUDE] == (1, 1, 1) and fits[OperatorType.BEVEL] == (1, 0, 0)
    assert fits[OperatorType.SWEEP] == (0, 1, 0) and fits[OperatorType.ADDSUB] == (0, 0, 1)
    face_id, strokes = _scene()
    assert _tokens(net, strokes, face_id).cls[-len(CLASSES) :].tolist() == count_fits(3)


def test_strokes_whose_ends_meet_attend_to_each_other_by_the_end_bias(net):
    face_id, strokes = _scene()  # strokes 0 and 1 share an end; stroke 2 lies apart
    a = _tokens(net, strokes, face_id)
    b = _tokens(net, strokes[:1], face_id)
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
    face_id, strokes = _scene()  # stroke 0 lies on face 3, stroke 2 on face 7
    t = _tokens(net, strokes, face_id)
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


def test_painted_roles_reproduce_the_generators_curve_label():
    _, strokes = _scene()
    labels = [2, 0, 1]
    truth = stroke_maps(strokes, labels, SIZE, SIZE).curve_label
    assert np.array_equal(paint_curve(strokes, labels, SIZE), truth)


def test_painted_face_map_shows_the_chosen_face_and_orders_the_rest():
    face_id, _ = _scene()
    f = paint_face(torch.tensor([0.3, 0.7]), torch.tensor([3, 7]), face_id, 1)
    assert np.array_equal(f > 0.5, face_id == 7)
    assert 0 < f[face_id == 3].max() <= 0.5 and f[face_id < 0].max() == 0
    f = paint_face(torch.tensor([0.3, 0.7]), torch.tensor([3, 7]), face_id, 0)
    assert np.array_equal(f > 0.5, face_id == 3)  # chosen with the roles, not the likeliest


def test_predictor_answers_as_the_unet_until_it_observes_a_sketch(net, tmp_path):
    face_id, strokes = _scene()
    head = StructureHead(HeadConfig(channels=feature_channels(net), width=16, layers=1))
    p = StructuredPredictor(net, head, threads=1)
    x = np.random.default_rng(0).random((5, SIZE, SIZE)).astype(np.float32)
    unet = net.predict(torch.from_numpy(x)[None])
    assert np.allclose(p.classify(x), unet[0][0].numpy(), atol=1e-6)
    p.observe(strokes, face_id)
    x2 = x.copy()
    probs = p.classify(x2)
    assert probs.shape == (4,) and abs(probs.sum() - 1) < 1e-5
    for op in CLASSES:
        f, c = p.segment(x2, op)
        roles = p.stroke_roles(x2, op)
        assert roles.shape == (3, ROLES[CLASSES.index(op)])
        assert np.array_equal(
            c, paint_curve(strokes, decode_roles(torch.from_numpy(roles), CLASSES.index(op)), SIZE)
        )
        faces = p.face_probabilities(x2, op)
        assert set(faces) == {3, 7} and abs(sum(faces.values()) - 1) < 1e-5
        best = max(faces, key=faces.get)
        assert np.array_equal(f > 0.5, face_id == best)
    x3 = x2.copy()  # inputs of a sketch it did not observe: never read with stale strokes
    assert np.allclose(p.segment(x3, CLASSES[0])[1], unet[2][0, 0].numpy(), atol=1e-6)


def test_a_head_loads_back_and_refuses_another_unets_features(net, tiny_config, tmp_path):
    head = StructureHead(HeadConfig(channels=feature_channels(net), width=16, layers=1))
    unet = tmp_path / "unet.pt"
    save_checkpoint(unet, net)
    save_head(tmp_path / "head.pt", head, unet_sha256="0" * 64)
    loaded, _ = load_head(tmp_path / "head.pt")
    for a, b in zip(head.state_dict().values(), loaded.state_dict().values(), strict=True):
        assert torch.equal(a, b)
    with pytest.raises(ValueError, match="another U-Net"):
        load_structured_predictor(tmp_path / "head.pt", unet)
    (tmp_path / "junk.pt").write_bytes(b"not a checkpoint")
    with pytest.raises(ValueError, match="sketch2cad-head"):
        load_head(tmp_path / "junk.pt")


def _two_normals() -> np.ndarray:
    """Normal images (Tokens.normal_image) of two face tokens, faces 3 and 7: face 3's
    normal points up the image and face 7's down, both seen at a slant."""
    return np.array([[0.0, -0.8], [0.0, 0.8]])


def _logits(probs: list[list[float]], op: int) -> torch.Tensor:
    """(S, 10) role logits whose operator-op probabilities are `probs`."""
    out = torch.full((len(probs), sum(ROLES)), -30.0)
    off = sum(ROLES[:op])
    out[:, off : off + ROLES[op]] = torch.tensor(probs).log()
    return out


def test_a_prism_is_read_as_its_drawing_allows():
    # the head's likeliest roles take a side edge for an outline side and that side for a
    # side edge; counts alone keep that (3 of each), the drawing's corners do not
    addsub = CLASSES.index(OperatorType.ADDSUB)
    strokes, truth = prism_drawing(3, 0, shift=(0.0, -70.0))  # the end outline above
    probs = [
        [0.8, 0.1, 0.1] if t == START else [0.1, 0.8, 0.1] if t == PROFILE else [0.1, 0.1, 0.8]
        for t in truth
    ]
    s, p = truth.index(START), truth.index(PROFILE)
    probs[s], probs[p] = [0.3, 0.6, 0.1], [0.6, 0.3, 0.1]
    faces = torch.tensor([[0.0] * 4, [0.0] * 4])
    assert decode_roles(role_probabilities(_logits(probs, addsub), addsub), addsub) != truth
    c = choose(_logits(probs, addsub), faces, addsub, strokes, _two_normals(), 256)
    assert c.roles == truth and c.face == 0  # face 3, whose normal points to the end


def test_the_end_outline_lies_from_the_start_along_the_chosen_faces_normal():
    # the head is a little surer of face 7, whose normal points away from where the
    # strokes it reads as the end outline lie: the pair of face 3 and those roles wins
    sweep = CLASSES.index(OperatorType.SWEEP)
    t = np.linspace(0, 2 * np.pi, 40)
    ring = np.stack([30 * np.cos(t), 10 * np.sin(t)], 1)
    strokes = [
        ring + (128, 180),
        np.array([[98.0, 180.0], [98.0, 100.0]]),
        np.array([[158.0, 180.0], [158.0, 100.0]]),
        ring + (128, 100),
    ]
    sure = [[0.9, 0.05, 0.05], [0.05, 0.9, 0.05], [0.05, 0.9, 0.05], [0.05, 0.05, 0.9]]
    faces = torch.tensor([[0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.5]])
    c = choose(_logits(sure, sweep), faces, sweep, strokes, _two_normals(), 256)
    assert c.roles == [START, PROFILE, PROFILE, END] and c.face == 0
    # and where the head is sure of face 7 but not of which circle starts, the face
    # says: the circle up the image (along face 7's normal, down) is the start
    unsure = [[0.45, 0.1, 0.45], sure[1], sure[2], [0.45, 0.1, 0.45]]
    faces = torch.tensor([[0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 5.0]])
    c = choose(_logits(unsure, sweep), faces, sweep, strokes, _two_normals(), 256)
    assert c.roles == [END, PROFILE, PROFILE, START] and c.face == 1


def test_a_bevels_copy_lies_from_its_profile_along_the_crease_down_the_chosen_faces_normal():
    # l' is l moved along the crease, -n_f. The head is surer of face 1 with the lower
    # stroke as l; from there the upper stroke lies 45 degrees off -n_1's image (face 1's
    # normal points down-left), which a crease cannot do: face 0 (normal up the image)
    # with the upper stroke as l is read instead
    bevel = CLASSES.index(OperatorType.BEVEL)
    x = np.linspace(-20.0, 20.0, 20)
    arc = np.stack([120.0 + x, 90.0 + 0.02 * x**2], 1)
    strokes = [arc, arc + (0.0, 80.0)]  # l on top, l' 80 px below it
    normals = np.array([[0.0, -0.8], [-0.57, 0.57]])
    lower_as_l = [[0.6, 0.4], [0.3, 0.7]]  # (l', l) probabilities per stroke
    faces = torch.tensor([[0.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]])
    alone = choose(_logits(lower_as_l, bevel), faces, bevel, strokes, np.zeros((2, 2)), 256)
    assert alone.roles == [BEVEL_L_PRIME, BEVEL_L] and alone.face == 1  # head-on: no tie
    c = choose(_logits(lower_as_l, bevel), faces, bevel, strokes, normals, 256)
    assert c.roles == [BEVEL_L, BEVEL_L_PRIME] and c.face == 0
