# SPDX-License-Identifier: LGPL-2.1-or-later
"""The networks of the paper's "Context Driven Sketch Interpretation", sized for a CPU.

The paper trains a VGG-like classifier and one two-branch U-Net per operator, all on
5 x 256 x 256 inputs (sketch S, depth D, normal N) with 32..512 channels, on 4 GPUs.
Training from scratch here must fit in 2 hours on 2 CPU cores, so one small network
does all five jobs (benchmarks/bench_networks.py measures the choices):

    x (B, 5, 256, 256)                       S, D, N at full size
      pool -> (B, 5, I, I)                   I = 128: max-pool S (1-px strokes survive),
                                             area-average D and N (edges stay sub-pixel)
      encoder, widths w0..w4                 (B, w_l, I/2^l, I/2^l), l = 0..4
        classifier on the bottleneck         global mean + max -> MLP -> (B, 4) logits
      decoder with skips -> (B, w0, I, I)
      heads, 1x1 conv -> (B, 2 x 4, I, I)    per operator: base-face logit F, curve C
      upsample bilinear -> (B, 4, 256, 256)  F probabilities and C at the input's size

Why one shared encoder: the four segmentation tasks and the classification all read
the same cues (where the strokes are, which planar region of D/N they sit on), so one
encoder trained on every sample learns them from four times the data that a
per-operator U-Net would see in the same time, and a sketch costs one pass instead of
two. The per-operator 1x1 heads keep the paper's per-operator outputs (each operator
has its own C encoding); the loss reaches only the ground-truth operator's heads.
Why I = 128: the strokes are one pixel wide at 256 and survive max-pooling; a U-Net
costs about 4x less per halving of the side, and 96 measured no faster per sample
than 128 once the smaller maps stop filling the cores (bench_networks.py).

Labels stay at full size: the outputs are upsampled before the loss, so training
optimises exactly the maps that the fitting stage and the evaluation read.
"""

from __future__ import annotations

import copy
from dataclasses import asdict, dataclass, fields
from pathlib import Path

import torch
import torch.nn as nn
import torch.nn.functional as F
from torch.nn.utils.fusion import fuse_conv_bn_eval

from ..brep.files import atomic_path
from ..sketch.labels import CLASSES

N_OPS = len(CLASSES)
IN_CHANNELS = 5  # S, D, N (datagen/sample.py)
CHECKPOINT_FORMAT = "sketch2cad-net"


@dataclass
class ModelConfig:
    """Architecture settings; saved in every checkpoint, so a file rebuilds its model.

    Attributes:
        image_size: side of the input and output maps (pixels).
        internal_size: side the network works at; inputs are pooled down to it.
        widths: encoder channels per level, finest first; the decoder mirrors them.
        classifier_hidden: width of the classifier's hidden layer.
        dropout: dropout before the classifier's last layer.
    """

    image_size: int = 256
    internal_size: int = 128
    widths: tuple[int, ...] = (8, 16, 32, 64, 128)
    classifier_hidden: int = 64
    dropout: float = 0.1

    def __post_init__(self):
        self.widths = tuple(int(w) for w in self.widths)
        levels = len(self.widths) - 1
        if self.internal_size % (2**levels):
            raise ValueError(
                f"internal_size {self.internal_size} must be divisible by "
                f"2^{levels} for {len(self.widths)} encoder levels"
            )


class ConvBlock(nn.Sequential):
    """Two 3x3 conv + batch norm + ReLU: (B, cin, H, W) -> (B, cout, H, W)."""

    def __init__(self, cin: int, cout: int):
        super().__init__(
            nn.Conv2d(cin, cout, 3, padding=1, bias=False),
            nn.BatchNorm2d(cout),
            nn.ReLU(inplace=True),
            nn.Conv2d(cout, cout, 3, padding=1, bias=False),
            nn.BatchNorm2d(cout),
            nn.ReLU(inplace=True),
        )


class Sketch2CADNet(nn.Module):
    """Operator classification and, per operator, base-face and curve segmentation."""

    def __init__(self, config: ModelConfig | None = None):
        super().__init__()
        self.config = cfg = config or ModelConfig()
        w = cfg.widths
        self.encoder = nn.ModuleList(
            [ConvBlock(IN_CHANNELS, w[0])] + [ConvBlock(w[i - 1], w[i]) for i in range(1, len(w))]
        )
        self.classifier = nn.Sequential(
            nn.Linear(2 * w[-1], cfg.classifier_hidden),
            nn.ReLU(inplace=True),
            nn.Dropout(cfg.dropout),
            nn.Linear(cfg.classifier_hidden, N_OPS),
        )
        self.up = nn.ModuleList(
            [nn.ConvTranspose2d(w[i], w[i - 1], 2, stride=2) for i in range(len(w) - 1, 0, -1)]
        )
        self.decoder = nn.ModuleList(
            [ConvBlock(2 * w[i - 1], w[i - 1]) for i in range(len(w) - 1, 0, -1)]
        )
        self.heads = nn.Conv2d(w[0], 2 * N_OPS, 1)  # channels: F logits of 4 ops, then C
        with torch.no_grad():  # start C at the middle of the labels' range 0..2
            self.heads.bias[N_OPS:].fill_(1.0)
        # channels-last: oneDNN's preferred layout on the CPU (docs/measurements.md, "The
        # U-Net in channels-last layout"); loading a state dict keeps the layout
        self.to(memory_format=torch.channels_last)

    # ------------------------------------------------------------ shapes
    def check_input(self, x: torch.Tensor, size: int, where: str) -> None:
        """Raise ValueError naming the expected shape when x is not (B, 5, size, size)."""
        if x.dim() == 4 and x.shape[1] == IN_CHANNELS and tuple(x.shape[2:]) == (size, size):
            return
        hint = ""
        if x.dim() == 3:
            hint = " (one sketch? add the batch axis: x[None])"
        elif x.dim() == 4 and tuple(x.shape[2:]) == (self.config.image_size,) * 2:
            hint = " (full-size maps: call predict(x), or pool(x) before forward)"
        elif x.dim() == 4 and tuple(x.shape[2:]) == (self.config.internal_size,) * 2:
            hint = " (pooled maps: call forward(x); predict takes full-size maps)"
        raise ValueError(
            f"Sketch2CADNet.{where} expects a float tensor of shape "
            f"(B, {IN_CHANNELS}, {size}, {size}) holding S, D, N stacked as "
            f"datagen/sample.py Sample.inputs() does, got {tuple(x.shape)}{hint}"
        )

    def pool(self, x: torch.Tensor) -> torch.Tensor:
        """Full-size (B, 5, S, S) -> (B, 5, I, I): max for the strokes S, mean for D, N."""
        self.check_input(x, self.config.image_size, "pool")
        factor, rest = divmod(self.config.image_size, self.config.internal_size)
        if rest:  # a size that is no multiple of I (the 96 of bench_networks' candidates)
            size = (self.config.internal_size,) * 2
            return torch.cat(
                [F.adaptive_max_pool2d(x[:, :1], size), F.adaptive_avg_pool2d(x[:, 1:], size)],
                dim=1,
            )
        # the adaptive pools' numbers (to float rounding) as f^2 strided slices, in a fifth
        # of their time on one sketch (0.52 -> 0.13 ms)
        cells = [x[:, :, i::factor, j::factor] for i in range(factor) for j in range(factor)]
        strokes, rest = cells[0][:, :1], cells[0][:, 1:]
        for cell in cells[1:]:
            strokes = torch.maximum(strokes, cell[:, :1])
            rest = rest + cell[:, 1:]
        return torch.cat([strokes, rest / factor**2], dim=1)

    def upsample(self, maps: torch.Tensor) -> torch.Tensor:
        """(B, K, I, I) -> (B, K, S, S), bilinear: the outputs at the input's size."""
        return F.interpolate(
            maps, size=(self.config.image_size,) * 2, mode="bilinear", align_corners=False
        )

    def fused(self) -> Sketch2CADNet:
        """An eval-mode copy for inference with each batch norm folded into the
        convolution before it (its running statistics are constants there): the same
        outputs within float rounding, 0.45 ms a sketch less of the U-Net's 4.5."""
        out = copy.deepcopy(self).eval()
        for block in out.modules():
            if isinstance(block, nn.Sequential):
                for i in range(len(block) - 1):
                    if isinstance(block[i], nn.Conv2d) and isinstance(block[i + 1], nn.BatchNorm2d):
                        block[i] = fuse_conv_bn_eval(block[i], block[i + 1])
                        block[i + 1] = nn.Identity()
        return out.to(memory_format=torch.channels_last)

    # ------------------------------------------------------------ passes
    def forward(self, x: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        """Pooled inputs -> outputs at the internal size.

        Args:
            x: (B, 5, I, I) float, `pool` of the full-size maps.
        Returns:
            logits (B, 4) of the operator classes, F logits (B, 4, I, I) and C values
            (B, 4, I, I), one channel per operator in OperatorType order.
        """
        logits, f, c, _ = self.features(x)
        return logits, f, c

    def features(
        self, x: torch.Tensor
    ) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor, list[torch.Tensor]]:
        """`forward`, plus the decoder's feature maps that the structured heads
        (inference/head/) pool along strokes and over faces.

        Returns:
            forward's three outputs and the decoder maps, coarsest first:
            (B, w_l, I/2^l, I/2^l) for l = len(widths) - 2 .. 0.
        """
        self.check_input(x, self.config.internal_size, "forward")
        skips, decoded = [], []
        h = x.contiguous(memory_format=torch.channels_last)
        for level, block in enumerate(self.encoder):
            h = block(h if level == 0 else F.max_pool2d(h, 2))  # (B, w_l, I/2^l, I/2^l)
            skips.append(h)
        logits = self.classifier(torch.cat([h.mean((2, 3)), h.amax((2, 3))], 1))  # (B, 4)
        for up, block, skip in zip(self.up, self.decoder, reversed(skips[:-1]), strict=True):
            h = block(torch.cat([up(h), skip], 1))  # (B, w_l, I/2^l, I/2^l), l = 3..0
            decoded.append(h)
        out = self.heads(h)  # (B, 8, I, I)
        return logits, out[:, :N_OPS], out[:, N_OPS:], decoded

    @torch.inference_mode()
    def predict(self, x: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        """Full-size maps -> what the fitting stage reads, at full size.

        Args:
            x: (B, 5, S, S) float, S = config.image_size (256).
        Returns:
            class probabilities (B, 4); F (B, 4, S, S) base-face probabilities in 0..1;
            C (B, 4, S, S) curve values (paper encodings: extrude/bevel 0..1,
            add/sub and sweep 0..2).
        """
        self.eval()
        return self.full_size(*self(self.pool(x)))

    def full_size(
        self, logits: torch.Tensor, f: torch.Tensor, c: torch.Tensor
    ) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        """`forward`'s outputs -> `predict`'s (for a caller that ran `features` itself)."""
        up = self.upsample(torch.cat([f, c], 1))  # logits upsampled, then squashed: sharper
        return logits.softmax(1), up[:, :N_OPS].sigmoid(), up[:, N_OPS:]


def class_weights(counts: torch.Tensor) -> torch.Tensor:
    """The paper's w_O: inverse class frequencies normalised to sum to 1.

    Args:
        counts: (4,) training samples per operator (a missing class counts as 1).
    Returns:
        (4,) float32 weights.
    """
    inv = 1.0 / counts.clamp(min=1).float()
    return inv / inv.sum()


def loss_terms(
    model: Sketch2CADNet,
    outputs: tuple[torch.Tensor, torch.Tensor, torch.Tensor],
    op: torch.Tensor,
    face_label: torch.Tensor,
    curve_label: torch.Tensor,
    stroke_mask: torch.Tensor,
    weights: torch.Tensor,
    face_dice: float = 0.0,
) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """The paper's losses (Eqs. 1 and 2), averaged over a batch, plus an optional Dice term.

    Classification: -w_O log P_O (Eq. 1), averaged with PyTorch's weighted mean (divided
    by the batch's summed weights): in expectation a constant multiple of the plain mean,
    and on the same scale as the segmentation terms whatever the class frequencies.
    Segmentation (Eq. 2) on the ground-truth operator's F and C, upsampled to the labels'
    full size: (1/HW) ||F - F~||^2 + (1/|M~|) ||M~ (C - C~)||^2.
    face_dice > 0 adds face_dice (1 - 2 |F F~| / (|F| + |F~|)) per sample to the face term:
    the per-pixel mean lets a small base face (an extruded end, a bevelled strip: a few
    percent of the image) cost almost nothing when missed, while the soft Dice term
    weighs every sample's face equally whatever its size.

    Args:
        model: supplies the upsampling to full size.
        outputs: forward()'s (logits (B, 4), F logits (B, 4, I, I), C (B, 4, I, I)).
        op: (B,) int64 ground-truth operator indices.
        face_label, curve_label, stroke_mask: (B, S, S) float F~, C~, M~.
        weights: (4,) class weights (`class_weights`).
        face_dice: weight of the soft Dice term (0: the paper's loss exactly).
    Returns:
        (classification, face, curve) scalar losses.
    """
    logits, f_logits, curve = outputs
    cls = F.cross_entropy(logits, op, weight=weights)
    pick = op[:, None, None, None].expand(-1, 1, *f_logits.shape[2:])  # (B, 1, I, I)
    maps = model.upsample(torch.cat([f_logits.gather(1, pick), curve.gather(1, pick)], 1))
    f, c = maps[:, 0].sigmoid(), maps[:, 1]  # (B, S, S) each
    face = ((f - face_label) ** 2).mean((1, 2))
    if face_dice:
        overlap = 2 * (f * face_label).sum((1, 2)) + 1.0  # +1: an empty face has Dice 1
        face = face + face_dice * (1 - overlap / (f.sum((1, 2)) + face_label.sum((1, 2)) + 1.0))
    strokes = stroke_mask.sum((1, 2)).clamp(min=1)  # a sketch without strokes adds 0
    curve_loss = ((stroke_mask * (c - curve_label)) ** 2).sum((1, 2)) / strokes
    return cls, face.mean(), curve_loss.mean()


# ---------------------------------------------------------------- checkpoints
def save_checkpoint(path: str | Path, model: Sketch2CADNet, **extra) -> None:
    """Write the weights with the config that rebuilds the model, plus `extra` entries
    (training state, class counts, provenance). Written to a temporary name and renamed,
    so an interrupted save never leaves a broken file."""
    with atomic_path(path) as tmp:
        torch.save(
            {
                "format": CHECKPOINT_FORMAT,
                "config": asdict(model.config),
                "model": model.state_dict(),
                **extra,
            },
            tmp,
        )


def load_checkpoint(path: str | Path, map_location: str = "cpu") -> tuple[Sketch2CADNet, dict]:
    """Rebuild a model from a checkpoint file alone.

    Returns:
        the model (in eval mode) and the whole checkpoint dictionary.
    Raises:
        ValueError: when the file is not a Sketch2CAD network checkpoint (named, with why).

    A checkpoint is a pickle (it holds numpy scalars of the training log): load only the
    project's own files or files from a source you trust.
    """
    try:
        ckpt = torch.load(path, map_location=map_location, weights_only=False)
    except FileNotFoundError:
        raise
    except Exception as e:  # a truncated or foreign file: pickle, zip and torch errors alike
        raise ValueError(
            f"{path}: not a readable {CHECKPOINT_FORMAT} checkpoint "
            f"({type(e).__name__}: {str(e)[:120]})"
        ) from None
    if not isinstance(ckpt, dict) or ckpt.get("format") != CHECKPOINT_FORMAT:
        raise ValueError(f"{path}: not a {CHECKPOINT_FORMAT} checkpoint")
    known = {f.name for f in fields(ModelConfig)}
    try:
        model = Sketch2CADNet(
            ModelConfig(**{k: v for k, v in ckpt["config"].items() if k in known})
        )
        model.load_state_dict(ckpt["model"])
    except (KeyError, TypeError, RuntimeError) as e:
        raise ValueError(
            f"{path}: a {CHECKPOINT_FORMAT} checkpoint that does not rebuild "
            f"the network ({type(e).__name__}: {str(e)[:120]})"
        ) from None
    return model.eval(), ckpt


def count_parameters(model: nn.Module) -> int:
    return sum(p.numel() for p in model.parameters())


def flops_per_sample(config: ModelConfig) -> float:
    """Multiply-adds of one forward pass of the convolutions (the dominant cost)."""
    w, s = config.widths, config.internal_size
    total = 0.0
    for level, width in enumerate(w):
        area = (s / 2**level) ** 2
        cin = IN_CHANNELS if level == 0 else w[level - 1]
        total += area * 9 * (cin * width + width * width)  # encoder block
        if level < len(w) - 1:
            total += area * 9 * (2 * width * width + width * width)  # decoder block
            total += area * w[level + 1] * width  # transposed conv
    return total + s * s * w[0] * 2 * N_OPS
