# SPDX-License-Identifier: LGPL-2.1-or-later
"""The head's choice painted into the F and C maps the fitting and the metrics read."""

from __future__ import annotations

import numpy as np
import torch

from ...render.strokes import rasterize
from .decode import choose
from .tokens import Tokens


def paint_curve(strokes: list[np.ndarray], labels: list[int], size: int) -> np.ndarray:
    """C: each stroke's pixels carry its label, drawn as the data generator draws C~
    (datagen/strokes.py: the later stroke wins where strokes cross)."""
    return rasterize(strokes, size, size, [float(v) for v in labels])


def paint_face(
    face_probs: torch.Tensor, face_ids: torch.Tensor, face_id: np.ndarray, chosen: int
) -> np.ndarray:
    """F: 1 on the chosen face's pixels (index into face_ids); every other face gets at
    most 0.5 p / p_max (not above the 0.5 that counts as f, so the paper's IoU and the
    fitting's vote see one face, while the fitting's fallback order by mean F follows
    the head's probabilities)."""
    out = np.zeros(face_id.shape, np.float32)
    if not len(face_ids):
        return out
    p = face_probs.numpy()
    value = 0.5 * p / max(p.max(), 1e-12)
    value[chosen] = 1.0
    lut = np.zeros(int(face_id.max()) + 2, np.float32)  # its last entry (0) for -1
    lut[face_ids.numpy()] = value
    return lut[face_id]


def painted(
    role_logits: torch.Tensor,
    face_logits: torch.Tensor,
    op: int,
    strokes: list[np.ndarray],
    t: Tokens,
    face_id: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The head's reading of one sketch under operator op (`choose`) painted into the F
    and C maps the fitting and the paper's metrics read (`paint_face`, `paint_curve`).

    Args:
        role_logits: (S, sum(ROLES)), face_logits: (K', N_CLASSES) the head's outputs
        (K' >= K: padded); strokes: the S polylines; t: the sketch's tokens;
        face_id: (H, W) face-ID map.
    """
    c = choose(role_logits, face_logits, op, strokes, t.normal_image.numpy(), face_id.shape[-1])
    return (
        paint_face(face_logits[: len(t.face_ids), op].softmax(0), t.face_ids, face_id, c.face),
        paint_curve(strokes, c.roles, face_id.shape[-1]),
    )
