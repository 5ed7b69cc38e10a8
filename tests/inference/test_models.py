# SPDX-License-Identifier: LGPL-2.1-or-later
"""The network: shapes, the input check, checkpoints, and the paper's losses."""

import pytest
import torch
import torch.nn.functional as F

from Sketch2CADWorkbench.inference.models import (
    ModelConfig,
    Sketch2CADNet,
    class_weights,
    load_checkpoint,
    loss_terms,
    save_checkpoint,
)


def _batch(cfg: ModelConfig, n: int = 3, seed: int = 0):
    g = torch.Generator().manual_seed(seed)
    s = cfg.image_size
    x = torch.rand(n, 5, s, s, generator=g)
    mask = (torch.rand(n, s, s, generator=g) > 0.9).float()
    x[:, 0] = mask
    face = (torch.rand(n, s, s, generator=g) > 0.5).float()
    curve = torch.randint(0, 3, (n, s, s), generator=g).float() * mask
    op = torch.tensor([0, 2, 3])[:n]
    return x, face, curve, mask, op


def test_forward_and_backward_give_the_documented_shapes_and_reach_every_parameter(tiny_config):
    torch.manual_seed(0)
    model = Sketch2CADNet(tiny_config)
    x, face, curve, mask, op = _batch(tiny_config)
    i = tiny_config.internal_size
    pooled = model.pool(x)
    assert pooled.shape == (3, 5, i, i)
    logits, f, c = model(pooled)
    assert logits.shape == (3, 4) and f.shape == (3, 4, i, i) and c.shape == (3, 4, i, i)
    loss = sum(
        loss_terms(
            model, (logits, f, c), op, face, curve, mask, class_weights(torch.tensor([1, 1, 4, 2]))
        )
    )
    loss.backward()
    assert all(p.grad is not None and torch.isfinite(p.grad).all() for p in model.parameters())


def test_predict_returns_probabilities_and_maps_at_the_full_input_size(tiny_config):
    model = Sketch2CADNet(tiny_config)
    x = _batch(tiny_config)[0]
    probs, f, c = model.predict(x)
    s = tiny_config.image_size
    assert probs.shape == (3, 4) and torch.allclose(probs.sum(1), torch.ones(3))
    assert f.shape == (3, 4, s, s) and c.shape == (3, 4, s, s)
    assert f.min() >= 0 and f.max() <= 1
    assert not f.requires_grad and torch.is_inference(f)


def test_the_default_model_maps_256_inputs_to_256_outputs():
    model = Sketch2CADNet()
    probs, f, c = model.predict(torch.zeros(1, 5, 256, 256))
    assert probs.shape == (1, 4) and f.shape == c.shape == (1, 4, 256, 256)


@pytest.mark.parametrize(
    "shape, hint",
    [
        ((5, 32, 32), "x[None]"),
        ((2, 3, 32, 32), "got (2, 3, 32, 32)"),
        ((2, 5, 16, 16), "pooled maps: call forward"),
    ],
)
def test_a_wrong_input_shape_says_what_is_expected_and_what_to_do(tiny_config, shape, hint):
    model = Sketch2CADNet(tiny_config)
    with pytest.raises(ValueError, match=r"\(B, 5, 32, 32\) holding S, D, N") as err:
        model.predict(torch.zeros(shape))
    assert hint in str(err.value)
    with pytest.raises(ValueError, match="call predict"):
        model(torch.zeros(1, 5, 32, 32))


def test_the_config_rejects_a_size_the_encoder_cannot_halve():
    with pytest.raises(ValueError, match="divisible"):
        ModelConfig(internal_size=100, widths=(8, 16, 32, 64))


def test_a_checkpoint_rebuilds_an_identical_model_from_the_file_alone(tiny_config, tmp_path):
    torch.manual_seed(1)
    model = Sketch2CADNet(tiny_config)
    model.train()
    model(model.pool(_batch(tiny_config)[0]))  # moves the batch-norm statistics
    save_checkpoint(tmp_path / "net.pt", model, note="hello")
    back, ckpt = load_checkpoint(tmp_path / "net.pt")
    assert back.config == tiny_config and ckpt["note"] == "hello"
    assert all(
        torch.equal(a, b)
        for a, b in zip(model.state_dict().values(), back.state_dict().values(), strict=True)
    )
    x = _batch(tiny_config, seed=5)[0]
    for a, b in zip(model.predict(x), back.predict(x), strict=True):
        assert torch.equal(a, b)


def test_the_inference_copy_folds_batch_norm_and_answers_as_the_model(tiny_config):
    torch.manual_seed(1)
    model = Sketch2CADNet(tiny_config)
    with torch.no_grad():  # batch norms that are not the identity
        for m in model.modules():
            if isinstance(m, torch.nn.BatchNorm2d):
                m.weight.uniform_(0.5, 2.0)
                m.bias.uniform_(-0.5, 0.5)
    model.train()
    for _ in range(3):
        model(model.pool(_batch(tiny_config)[0]))  # moves the running statistics
    model.eval()
    fused = model.fused()
    assert not any(isinstance(m, torch.nn.BatchNorm2d) for m in fused.modules())
    assert any(isinstance(m, torch.nn.BatchNorm2d) for m in model.modules())  # untouched
    x = _batch(tiny_config, seed=5)[0]
    for a, b in zip(model.predict(x), fused.predict(x), strict=True):
        assert torch.allclose(a, b, atol=1e-4)


def test_loading_something_else_than_a_checkpoint_fails_clearly(tmp_path):
    torch.save({"weights": 1}, tmp_path / "other.pt")
    with pytest.raises(ValueError, match="not a sketch2cad-net checkpoint"):
        load_checkpoint(tmp_path / "other.pt")


def test_class_weights_are_normalised_inverse_frequencies():
    w = class_weights(torch.tensor([100, 100, 400, 200]))
    assert torch.allclose(w, torch.tensor([4.0, 4.0, 1.0, 2.0]) / 11)
    assert torch.isclose(w.sum(), torch.tensor(1.0))


def _full_size_config():
    """No pooling: every output pixel is one label pixel, so masks are exact."""
    return ModelConfig(image_size=8, internal_size=8, widths=(2, 4), classifier_hidden=4)


def test_the_losses_are_the_papers_formulas():
    model = Sketch2CADNet(_full_size_config())
    logits = torch.tensor([[2.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]])
    f = torch.zeros(2, 4, 8, 8)  # F = sigmoid(0) = 0.5 everywhere
    c = torch.ones(2, 4, 8, 8)
    op = torch.tensor([0, 2])
    face = torch.ones(2, 8, 8)  # (F - F~)^2 = 0.25 at every pixel
    mask = torch.zeros(2, 8, 8)
    mask[:, 0, :4] = 1  # 4 stroke pixels per sample
    curve = torch.zeros(2, 8, 8)
    curve[1, 0, :2] = 2  # errors 1, 1, 1, 1 and 1, 1, 1, 1
    weights = torch.tensor([0.4, 0.4, 0.1, 0.1])
    cls, fl, cl = loss_terms(model, (logits, f, c), op, face, curve, mask, weights)
    nll = -F.log_softmax(logits, 1)[[0, 1], [0, 2]]
    assert torch.isclose(cls, (0.4 * nll[0] + 0.1 * nll[1]) / 0.5)
    assert torch.isclose(fl, torch.tensor(0.25))
    assert torch.isclose(cl, torch.tensor(1.0))


def test_the_dice_term_makes_a_missed_small_face_cost_as_much_as_a_missed_large_one():
    model = Sketch2CADNet(_full_size_config())
    logits, c = torch.zeros(2, 4), torch.zeros(2, 4, 8, 8)
    f = torch.full((2, 4, 8, 8), -20.0)  # F = 0: both faces missed entirely
    face = torch.zeros(2, 8, 8)
    face[0, :1, :2] = 1  # 2 pixels
    face[1, :6, :6] = 1  # 36 pixels
    args = (
        torch.tensor([0, 0]),
        face,
        torch.zeros(2, 8, 8),
        torch.zeros(2, 8, 8),
        torch.full((4,), 0.25),
    )

    def face_terms(dice):  # per sample: a batch of one each
        return [
            float(
                loss_terms(
                    model,
                    (logits[k : k + 1], f[k : k + 1], c[k : k + 1]),
                    *(a[k : k + 1] for a in args[:4]),
                    args[4],
                    face_dice=dice,
                )[1]
            )
            for k in (0, 1)
        ]

    mse_small, mse_large = face_terms(0.0)
    dice_small, dice_large = face_terms(1.0)
    assert mse_small < mse_large / 10  # the paper's term barely sees it
    assert dice_small - mse_small > 0.6 and dice_large - mse_large > 0.9


def test_the_curve_loss_sees_stroke_pixels_only():
    model = Sketch2CADNet(_full_size_config())
    g = torch.Generator().manual_seed(0)
    logits, f, c = (
        torch.randn(2, 4, generator=g),
        torch.randn(2, 4, 8, 8, generator=g),
        torch.randn(2, 4, 8, 8, generator=g),
    )
    op = torch.tensor([1, 3])
    face = (torch.rand(2, 8, 8, generator=g) > 0.5).float()
    mask = (torch.rand(2, 8, 8, generator=g) > 0.7).float()
    curve = torch.randint(0, 3, (2, 8, 8), generator=g).float() * mask
    weights = torch.full((4,), 0.25)
    before = loss_terms(model, (logits, f, c), op, face, curve, mask, weights)
    off = (mask == 0)[:, None].expand_as(c)
    c2 = torch.where(off, c + 10 * torch.randn(c.shape, generator=g), c)
    curve2 = torch.where(mask == 0, torch.full_like(curve, 7.0), curve)
    after = loss_terms(model, (logits, f, c2), op, face, curve2, mask, weights)
    assert torch.equal(before[2], after[2])
    on = (mask > 0)[:, None].expand_as(c)
    assert not torch.equal(
        before[2],
        loss_terms(model, (logits, f, torch.where(on, c + 1, c)), op, face, curve, mask, weights)[
            2
        ],
    )


def test_only_the_true_operators_heads_get_the_segmentation_loss(tiny_config):
    model = Sketch2CADNet(tiny_config)
    x, face, curve, mask, _ = _batch(tiny_config, n=1)
    logits, f, c = model(model.pool(x))
    f.retain_grad()
    c.retain_grad()
    _, fl, cl = loss_terms(
        model, (logits, f, c), torch.tensor([2]), face, curve, mask, torch.full((4,), 0.25)
    )
    (fl + cl).backward()
    assert f.grad[0, 2].abs().sum() > 0 and c.grad[0, 2].abs().sum() > 0
    assert f.grad[0, [0, 1, 3]].abs().sum() == 0 and c.grad[0, [0, 1, 3]].abs().sum() == 0


def test_pooling_keeps_one_pixel_strokes_and_averages_depth(tiny_config):
    model = Sketch2CADNet(tiny_config)
    x = torch.zeros(1, 5, 32, 32)
    x[0, 0, 7, :] = 1  # a one-pixel line on an odd row
    x[0, 1, :2, :2] = torch.tensor([[0.0, 0.4], [0.4, 0.8]])
    p = model.pool(x)
    assert torch.equal(p[0, 0, 3], torch.ones(16)) and p[0, 0].sum() == 16
    assert torch.isclose(p[0, 1, 0, 0], torch.tensor(0.4))
