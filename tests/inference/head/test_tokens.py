# SPDX-License-Identifier: LGPL-2.1-or-later
"""A sketch's tokens: one per stroke and per visible face, and the class token."""

import numpy as np
import torch
import torch.nn.functional as F
from head_fixtures import SIZE, scene, scene_tokens

from Sketch2CADWorkbench.brep.protocol import OperatorType
from Sketch2CADWorkbench.inference.head.tokens import (
    POINTS,
    STROKE_GEOMETRY,
    _Polylines,
    count_fits,
    feature_channels,
    feature_maps,
    stroke_geometry,
    tokens,
)
from Sketch2CADWorkbench.inference.models import ModelConfig, Sketch2CADNet
from Sketch2CADWorkbench.sketch.labels import CLASSES


def test_one_token_per_stroke_and_per_visible_face(net):
    face_id, strokes = scene()
    t = scene_tokens(net, strokes, face_id)
    c = feature_channels(net)
    assert t.stroke.shape == (3, 2 * c + STROKE_GEOMETRY)
    assert sorted(t.face_ids.tolist()) == [3, 7]
    assert t.face.shape[0] == 2 and torch.isfinite(t.face).all() and torch.isfinite(t.stroke).all()


def test_a_face_token_holds_its_area_centroid_and_spread(net):
    face_id, strokes = scene()
    t = scene_tokens(net, strokes, face_id)
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
    face_id, strokes = scene()
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
    face_id, strokes = scene()
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
    face_id, strokes = scene()
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
    face_id, strokes = scene()
    forward = scene_tokens(net, strokes, face_id)
    backward = scene_tokens(net, [s[::-1] for s in strokes], face_id)
    assert torch.allclose(forward.stroke, backward.stroke, atol=1e-5)
    normal = np.array([[0.3, 0.4]] * len(strokes))
    assert np.allclose(
        stroke_geometry(strokes, normal, SIZE),
        stroke_geometry([s[::-1] for s in strokes], normal, SIZE),
        atol=1e-6,
    )


def test_a_sketch_without_faces_in_view_still_gives_stroke_tokens(net):
    _, strokes = scene()
    t = scene_tokens(net, strokes, np.full((SIZE, SIZE), -1, np.int16))
    assert t.stroke.shape[0] == 3 and t.face.shape[0] == 0


def test_the_class_token_says_which_drawings_have_that_many_strokes(net):
    fits = dict(
        zip(CLASSES, zip(count_fits(2), count_fits(4), count_fits(9), strict=False), strict=False)
    )
    assert fits[OperatorType.EXTRUDE] == (1, 1, 1) and fits[OperatorType.BEVEL] == (1, 0, 0)
    assert fits[OperatorType.SWEEP] == (0, 1, 0) and fits[OperatorType.ADDSUB] == (0, 0, 1)
    face_id, strokes = scene()
    assert scene_tokens(net, strokes, face_id).cls[-len(CLASSES) :].tolist() == count_fits(3)
