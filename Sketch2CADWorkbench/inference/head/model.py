# SPDX-License-Identifier: LGPL-2.1-or-later
"""The structured head: a small transformer over one sketch's tokens.

    StructureHead(HeadConfig())(*collate([tokens, ...])) -> class, role and face logits

A pre-norm transformer whose attention is biased by how near two strokes' ends lie and
by how much of a stroke lies on a face; one class token, the stroke tokens and the face
tokens in one sequence.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch
import torch.nn as nn
import torch.nn.functional as F

from ...sketch.labels import LABELLED
from ..models import N_OPS
from .tokens import CLASS_EXTRA, ENDS, FACE_GEOMETRY, STROKE_GEOMETRY, Tokens

# The head's classes (sketch/labels.py LABELLED): the U-Net's four and the shell, whose
# logit has no U-Net logit under it (the correction alone).
N_CLASSES = len(LABELLED)
# Stroke roles per class (the curve label encodings of sketch/labels.py).
ROLES = (2, 2, 3, 3, 2)
ROLE_OFFSETS = tuple(int(v) for v in np.cumsum((0,) + ROLES[:-1]))


# Gaps between stroke ends (image widths) that the end bias tells apart: level-3 noise
# moves an end by about 0.03, the sides of a small prism are about 0.1 long.
END_GAP_BINS = (0.01, 0.02, 0.04, 0.08, 0.16)


# Shares of a stroke's points on a face that the face bias tells apart: none, a corner's
# worth, part, most, all (a start stroke lies on the base face, an end stroke leaves it).
ON_FACE_BINS = (0.05, 0.35, 0.65, 0.95)


@dataclass
class HeadConfig:
    """The head's settings; saved in its checkpoint, so a file rebuilds the head."""

    channels: int = 69  # feature_channels of the U-Net it reads
    width: int = 96
    layers: int = 3
    attention_heads: int = 4
    dropout: float = 0.1
    end_bias: bool = True  # attention between strokes biased by how near their ends lie
    face_bias: bool = True  # attention between a stroke and a face by how much it lies on it
    # the classes it tells apart: the first of LABELLED, 4 for a head of the U-Net's
    # classes alone (without the shell)
    classes: int = N_CLASSES


class AttentionLayer(nn.Module):
    """A pre-norm transformer layer whose attention adds a (B, heads, L, L) bias. Not
    torch's TransformerEncoderLayer: its fused inference path reads a per-sample 3-D
    mask otherwise than its training path (outputs differed by 0.6 in eval mode)."""

    def __init__(self, width: int, heads: int, dropout: float):
        super().__init__()
        self.heads, self.dropout = heads, dropout
        self.norm1, self.norm2 = nn.LayerNorm(width), nn.LayerNorm(width)
        self.qkv = nn.Linear(width, 3 * width)
        self.out = nn.Linear(width, width)
        self.feed = nn.Sequential(
            nn.Linear(width, 2 * width), nn.ReLU(), nn.Dropout(dropout), nn.Linear(2 * width, width)
        )
        self.drop = nn.Dropout(dropout)

    def forward(self, h: torch.Tensor, bias: torch.Tensor) -> torch.Tensor:
        """(B, L, width) tokens, (B, heads, L, L) bias -> (B, L, width)."""
        b, n, w = h.shape
        q, k, v = (
            self.qkv(self.norm1(h))
            .view(b, n, 3, self.heads, w // self.heads)
            .permute(2, 0, 3, 1, 4)
        )
        a = F.scaled_dot_product_attention(
            q, k, v, attn_mask=bias, dropout_p=self.dropout if self.training else 0.0
        )
        h = h + self.drop(self.out(a.transpose(1, 2).reshape(b, n, w)))
        return h + self.drop(self.feed(self.norm2(h)))


class StructureHead(nn.Module):
    """Transformer over one class token, the stroke tokens and the face tokens."""

    def __init__(self, config: HeadConfig | None = None):
        super().__init__()
        self.config = cfg = config or HeadConfig()
        w = cfg.width
        self.embed_cls = nn.Linear(N_OPS + CLASS_EXTRA, w)
        self.embed_stroke = nn.Sequential(
            nn.LayerNorm(2 * cfg.channels + STROKE_GEOMETRY),
            nn.Linear(2 * cfg.channels + STROKE_GEOMETRY, w),
        )
        self.embed_face = nn.Sequential(
            nn.LayerNorm(cfg.channels + FACE_GEOMETRY), nn.Linear(cfg.channels + FACE_GEOMETRY, w)
        )
        # layers = 0: every token read alone (the ablation of the context)
        self.layers = nn.ModuleList(
            AttentionLayer(w, cfg.attention_heads, cfg.dropout) for _ in range(cfg.layers)
        )
        # per attention head, a learned bias per END_GAP_BINS bin of two strokes' end gap:
        # the strokes of one outline meet end to end, which attention over coordinates
        # finds only approximately (see docs/measurements.md, head.model.END_GAP_BINS)
        self.end_bias = (
            nn.Embedding(len(END_GAP_BINS) + 1, cfg.attention_heads)
            if cfg.end_bias and cfg.layers
            else None
        )
        # and per bin of a stroke's share on a face, a bias each way (stroke to face, face
        # to stroke): which face a stroke lies on is in no token
        self.face_bias = (
            nn.Embedding(len(ON_FACE_BINS) + 1, 2 * cfg.attention_heads)
            if cfg.face_bias and cfg.layers
            else None
        )
        for bias in (self.end_bias, self.face_bias):
            if bias is not None:
                nn.init.zeros_(bias.weight)
        self.norm = nn.LayerNorm(w)
        self.cls_out = nn.Linear(w, cfg.classes)
        self.role_out = nn.Linear(w, sum(ROLES[: cfg.classes]))
        self.face_out = nn.Linear(w, cfg.classes)
        with torch.no_grad():  # start as the U-Net's classifier: a correction of its logits
            self.cls_out.weight.zero_()
            self.cls_out.bias.zero_()

    def _attention_bias(
        self, stroke: torch.Tensor, on_face: torch.Tensor, pad: torch.Tensor
    ) -> torch.Tensor:
        """(B, heads, L, L) additive attention mask: -inf on padded keys; between strokes
        the end bias of their nearest ends' gap bin; between a stroke and a face the face
        bias of the stroke's share on it."""
        b, n_s, heads = stroke.shape[0], stroke.shape[1], self.config.attention_heads
        n = pad.shape[1]
        mask = torch.zeros(b, heads, n, n).masked_fill(pad[:, None, None], float("-inf"))
        if self.end_bias is not None:
            geo = 2 * self.config.channels
            ends = stroke[..., geo + ENDS.start : geo + ENDS.stop].reshape(b, n_s, 2, 2)
            gap = (ends[:, :, None, :, None] - ends[:, None, :, None, :]).norm(dim=-1)
            bins = torch.bucketize(gap.amin((-2, -1)), torch.tensor(END_GAP_BINS))
            mask[:, :, 1 : 1 + n_s, 1 : 1 + n_s] += self.end_bias(bins).permute(0, 3, 1, 2)
        if self.face_bias is not None:
            bias = self.face_bias(torch.bucketize(on_face, torch.tensor(ON_FACE_BINS)))
            mask[:, :, 1 : 1 + n_s, 1 + n_s :] += bias[..., :heads].permute(0, 3, 1, 2)
            mask[:, :, 1 + n_s :, 1 : 1 + n_s] += bias[..., heads:].permute(0, 3, 2, 1)
        return mask

    def forward(
        self,
        cls: torch.Tensor,
        stroke: torch.Tensor,
        stroke_mask: torch.Tensor,
        face: torch.Tensor,
        face_mask: torch.Tensor,
        on_face: torch.Tensor,
    ) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        """Padded batch -> logits.

        Args:
            cls: (B, N_OPS + CLASS_EXTRA); stroke: (B, S, Ds), stroke_mask: (B, S) bool
            (True = real); face: (B, K, Df), face_mask: (B, K) bool; on_face: (B, S, K)
            each stroke's share on each face.
        Returns:
            class logits (B, classes) (the U-Net's plus a correction); role logits
            (B, S, sum(ROLES[:classes])) (class k's roles at ROLE_OFFSETS[k]); face
            logits (B, K, classes) (-inf on padding).
        """
        n_s = stroke.shape[1]
        h = torch.cat(
            [self.embed_cls(cls)[:, None], self.embed_stroke(stroke), self.embed_face(face)], 1
        )
        pad = torch.cat([torch.zeros_like(stroke_mask[:, :1]), ~stroke_mask, ~face_mask], 1)
        if len(self.layers):
            bias = self._attention_bias(stroke, on_face, pad)
            for layer in self.layers:
                h = layer(h, bias)
        h = self.norm(h)
        logits = F.pad(cls[:, :N_OPS], (0, self.config.classes - N_OPS)) + self.cls_out(h[:, 0])
        roles = self.role_out(h[:, 1 : 1 + n_s])
        faces = self.face_out(h[:, 1 + n_s :]).masked_fill(~face_mask[..., None], float("-inf"))
        return logits, roles, faces


def collate(items: list[Tokens]) -> tuple[torch.Tensor, ...]:
    """Tokens of several sketches -> the padded batch StructureHead.forward takes."""
    b = len(items)
    n_s = max(1, max(len(t.stroke) for t in items))
    n_f = max(1, max(len(t.face) for t in items))
    stroke = torch.zeros(b, n_s, items[0].stroke.shape[1])
    face = torch.zeros(b, n_f, items[0].face.shape[1])
    s_mask = torch.zeros(b, n_s, dtype=torch.bool)
    f_mask = torch.zeros(b, n_f, dtype=torch.bool)
    on_face = torch.zeros(b, n_s, n_f)
    for j, t in enumerate(items):
        stroke[j, : len(t.stroke)], s_mask[j, : len(t.stroke)] = t.stroke, True
        face[j, : len(t.face)], f_mask[j, : len(t.face)] = t.face, True
        on_face[j, : len(t.stroke), : len(t.face)] = t.on_face
    return torch.stack([t.cls for t in items]), stroke, s_mask, face, f_mask, on_face
