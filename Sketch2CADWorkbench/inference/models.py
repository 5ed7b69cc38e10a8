# SPDX-License-Identifier: LGPL-2.1-or-later
"""The networks: one small U-Net with a shared encoder for all three jobs of the paper.

The paper trains a VGG-like classifier and one two-branch U-Net per operator on 4 GPUs.
This machine has two CPU cores, so one network does it all:

    input (B, 5, 256, 256) S, D, N
      -> pooled to 128 x 128 (max for the thin strokes, mean for D and N)
      -> encoder 8-16-32-64-128 channels down to 8 x 8 (narrow where the maps are large:
         the cost of a level grows with its area)
      -> classifier head on the bottleneck: 4 operator logits
      -> decoder with skips back to 128 x 128 -> per operator: F logit and C value
         (8 channels), upsampled to 256 x 256

Operator-specific outputs keep the paper's per-operator segmentation (each operator's
C encoding differs) while sharing all features; the encoder also learns from every
sample instead of a quarter of them. The loss is the paper's, per sample applied to the
ground-truth operator's outputs (Eqs. 1-2).
"""
from __future__ import annotations

from dataclasses import asdict, dataclass

import torch
import torch.nn as nn
import torch.nn.functional as F

N_OPS = 4
IN_CHANNELS = 5


@dataclass
class NetConfig:
    """Architecture settings; saved in every checkpoint so it rebuilds the model alone."""

    widths: tuple[int, ...] = (8, 16, 32, 64, 128)
    internal: int = 128  # working resolution (input is pooled down to it)
    size: int = 256      # input/output resolution


def block(cin: int, cout: int) -> nn.Sequential:
    return nn.Sequential(nn.Conv2d(cin, cout, 3, padding=1, bias=False), nn.BatchNorm2d(cout),
                         nn.ReLU(inplace=True),
                         nn.Conv2d(cout, cout, 3, padding=1, bias=False), nn.BatchNorm2d(cout),
                         nn.ReLU(inplace=True))


class Sketch2CADNet(nn.Module):
    """Operator classification + per-operator base-face and curve segmentation."""

    def __init__(self, cfg: NetConfig = NetConfig()):
        super().__init__()
        self.cfg = cfg
        w = cfg.widths
        self.enc = nn.ModuleList([block(IN_CHANNELS, w[0])] +
                                 [block(w[i - 1], w[i]) for i in range(1, len(w))])
        self.cls = nn.Sequential(nn.Linear(2 * w[-1], 64), nn.ReLU(inplace=True),
                                 nn.Linear(64, N_OPS))
        self.up = nn.ModuleList([nn.ConvTranspose2d(w[i], w[i - 1], 2, stride=2)
                                 for i in range(len(w) - 1, 0, -1)])
        self.dec = nn.ModuleList([block(2 * w[i - 1], w[i - 1]) for i in range(len(w) - 1, 0, -1)])
        self.head = nn.Conv2d(w[0], 2 * N_OPS, 1)

    def check_input(self, x: torch.Tensor, size: int) -> None:
        if x.dim() != 4 or x.shape[1] != IN_CHANNELS or tuple(x.shape[2:]) != (size, size):
            raise ValueError(f"expected input of shape (B, {IN_CHANNELS}, {size}, {size}) "
                             f"holding S, D, N (see datagen/sample.py), got {tuple(x.shape)}")

    def forward(self, h: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        """Pooled input (B, 5, I, I) -> logits (B, 4), F logits (B, 4, I, I), C (B, 4, I, I).

        Training works at the internal resolution I (inputs and labels pooled once, see
        `pool_inputs`/`pool_labels`); `predict` takes full-size maps.
        """
        self.check_input(h, self.cfg.internal)
        skips = []
        for i, enc in enumerate(self.enc):
            h = enc(h if i == 0 else F.max_pool2d(h, 2))
            skips.append(h)
        logits = self.cls(torch.cat([h.mean((2, 3)), h.amax((2, 3))], dim=1))  # (B, 4)
        for up, dec, skip in zip(self.up, self.dec, reversed(skips[:-1])):
            h = dec(torch.cat([up(h), skip], dim=1))
        out = self.head(h)                           # (B, 8, I, I)
        return logits, out[:, :N_OPS], out[:, N_OPS:]

    @torch.inference_mode()
    def predict(self, x: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        """Full-size x (B, 5, S, S) -> probabilities (B, 4), F probabilities and C maps
        (B, 4, S, S) upsampled bilinearly for the fitting stage."""
        self.eval()
        self.check_input(x, self.cfg.size)
        logits, f, c = self(pool_inputs(x, self.cfg.size // self.cfg.internal))
        size = (self.cfg.size,) * 2
        up = F.interpolate(torch.cat([f, c], 1), size=size, mode="bilinear", align_corners=False)
        return logits.softmax(1), up[:, :N_OPS].sigmoid(), up[:, N_OPS:]


def _blocks(x: torch.Tensor, k: int) -> torch.Tensor:
    """(..., H, W) -> (..., H/k, W/k, k*k): the k x k blocks (a cheap exact pooling)."""
    *lead, h, w = x.shape
    return x.reshape(*lead, h // k, k, w // k, k).movedim(-3, -2).reshape(*lead, h // k, w // k, k * k)


def pool_inputs(x: torch.Tensor, k: int) -> torch.Tensor:
    """(B, 5, S, S) -> (B, 5, S/k, S/k): max for the thin strokes S, mean for D and N."""
    if k == 1:
        return x
    return torch.cat([_blocks(x[:, :1], k).amax(-1), _blocks(x[:, 1:], k).mean(-1)], dim=1)


def pool_labels(face: torch.Tensor, curve: torch.Tensor, mask: torch.Tensor, k: int
                ) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """Labels (B, S, S) at S/k: F~ averaged, M~ and C~ max-pooled over stroke pixels."""
    if k == 1:
        return face, curve, mask
    m = _blocks(mask, k).amax(-1)
    c = _blocks((curve + 1) * mask, k).amax(-1) - 1
    return _blocks(face, k).mean(-1), c.clamp(min=0) * m, m


def class_weights(counts: torch.Tensor) -> torch.Tensor:
    """The paper's w_O: inverse class frequencies, normalised to sum to 1."""
    inv = 1.0 / counts.clamp(min=1).float()
    return inv / inv.sum()


def loss_terms(logits, f_logits, c, op, face_label, curve_label, stroke_mask, weights
               ) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """The paper's losses for a batch, averaged over it.

    Classification: weighted cross entropy -w_O log P_O (Eq. 1; weights normalised by the
    batch's total weight). Segmentation (Eq. 2), on the ground-truth operator's outputs:
    (1/HW) ||F - F~||^2 + (1/|M~|) ||M~ (C - C~)||^2.
    """
    cls = F.cross_entropy(logits, op, weight=weights)
    idx = op[:, None, None, None].expand(-1, 1, *f_logits.shape[2:])
    f = torch.gather(f_logits, 1, idx)[:, 0].sigmoid()
    cc = torch.gather(c, 1, idx)[:, 0]
    face = ((f - face_label) ** 2).mean((1, 2))
    curve = ((stroke_mask * (cc - curve_label)) ** 2).sum((1, 2)) / stroke_mask.sum((1, 2)).clamp(min=1)
    return cls, face.mean(), curve.mean()


def save_checkpoint(path, model: Sketch2CADNet, extra: dict | None = None) -> None:
    """Weights plus the config that rebuilds the model (and any training state)."""
    torch.save({"config": asdict(model.cfg), "model": model.state_dict(), **(extra or {})}, path)


def load_model(path, map_location="cpu") -> tuple[Sketch2CADNet, dict]:
    """Rebuild a model from a checkpoint file alone; returns it and the whole checkpoint."""
    ckpt = torch.load(path, map_location=map_location, weights_only=False)
    cfg = ckpt["config"]
    model = Sketch2CADNet(NetConfig(tuple(cfg["widths"]), cfg["internal"], cfg["size"]))
    model.load_state_dict(ckpt["model"])
    return model, ckpt
