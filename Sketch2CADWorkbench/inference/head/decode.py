# SPDX-License-Identifier: LGPL-2.1-or-later
"""The head's outputs read as one choice: each stroke's role and the base face."""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
import torch
from scipy.optimize import linear_sum_assignment

from ...brep.protocol import OperatorType
from ...sketch.labels import BEVEL_L, BEVEL_L_PRIME, END, LABELLED, START
from ..drawing import prism_labellings
from ..fitting.stroke_roles import MIN_SIN
from .model import ROLE_OFFSETS, ROLES


def role_probabilities(roles: torch.Tensor, op: int) -> torch.Tensor:
    """(S, sum(ROLES)) role logits of one sketch -> (S, ROLES[op]) probabilities of class op."""
    return roles[:, ROLE_OFFSETS[op] : ROLE_OFFSETS[op] + ROLES[op]].softmax(-1)


def role_counts(op: int, strokes: int) -> tuple[int, ...] | None:
    """How many strokes take each role (curve label order) in a sketch of `strokes`
    strokes of operator op, where the operator's drawing fixes it: a bevel has exactly
    one profile l (paper, Fig. 7); a prism over an n-gon has n start, n profile and n end
    strokes; a sweep its start and end ellipses joined by 2 profiles. None: not fixed
    (an extrusion's offset strokes vary with the face), or a count the drawing cannot
    have (then each stroke takes its own likeliest role)."""
    kind = LABELLED[op]
    if kind is OperatorType.BEVEL and strokes:
        counts = [strokes - 1, strokes - 1]
        counts[BEVEL_L] = 1
        return tuple(counts)
    if kind is OperatorType.ADDSUB and strokes and strokes % 3 == 0:
        return (strokes // 3,) * 3
    if kind is OperatorType.SWEEP and strokes == 4:
        return (1, 2, 1)
    return None


def decode_roles(probs: torch.Tensor, op: int) -> list[int]:
    """Each stroke's curve label: the most likely labelling with `role_counts` strokes
    per role (an assignment of strokes to role slots), else each stroke's argmax. The
    counts turn a prism whose far outline the head half reads as start into n and n."""
    if not len(probs):
        return []
    counts = role_counts(op, len(probs))
    if counts is None:
        return [int(v) for v in probs.argmax(1)]
    slots = np.repeat(np.arange(len(counts)), counts)
    cost = -np.log(np.clip(probs.numpy()[:, slots], 1e-12, None))  # (strokes, slots)
    rows, cols = linear_sum_assignment(cost)
    labels = np.empty(len(probs), np.int64)
    labels[rows] = slots[cols]
    return [int(v) for v in labels]


@dataclass
class Choice:
    """The head's reading of one sketch under one operator."""

    roles: list[int]  # each stroke's curve label
    face: int  # the chosen face token (index into face_ids); -1: no face in view


# The two outlines each operator's drawing ties to n_f: (from, to, sign), the `to` outline
# lying from the `from` one along sign * n_f: a prism's or sweep's end outline from its
# start (sketch/curves.py orders them along n_f), a bevel's l' from l along its crease,
# which runs along -n_f (brep/corners.py CREASE_COS).
OUTLINES = {
    OperatorType.ADDSUB: (START, END, 1.0),
    OperatorType.SWEEP: (START, END, 1.0),
    OperatorType.BEVEL: (BEVEL_L, BEVEL_L_PRIME, -1.0),
}
# The least cosine between the image shift from one outline to the other (stroke
# midpoints) and sign * n_f's image that agrees. A bevel's copy l' is the whole stroke
# moved, so the shift keeps the crease's direction: 0.9 accepts 99% of the truths at
# noise level 3 (a validation set of seed 30017: 1% quantile .928; every one at level 1,
# heldout-l1c's lowest .985; see docs/measurements.md, head.decode.OUTLINE_SHIFT_COS). A prism's or
# a sweep's outlines are drawn side by side or as ellipses, whose midpoints the hand
# moves more (a short sweep's truth reaches -0.86 at level 3): the sign alone.
OUTLINE_SHIFT_COS = {OperatorType.ADDSUB: 0.0, OperatorType.SWEEP: 0.0, OperatorType.BEVEL: 0.9}


def _outline_labellings(op: int, strokes: list[np.ndarray], size: int) -> list[np.ndarray]:
    """The labellings a drawing of op with two outlines allows: a prism's from how its
    strokes meet (drawing.py), a sweep's any 1 / 2 / 1 split of its 4 strokes, a bevel's
    either of its 2 strokes as l (`count_fits`)."""
    kind = LABELLED[op]
    if kind is OperatorType.ADDSUB:
        return prism_labellings(strokes, size)
    if kind is OperatorType.SWEEP and len(strokes) == 4:
        return [np.array(p) for p in sorted(set(itertools.permutations((0, 1, 1, 2))))]
    if kind is OperatorType.BEVEL and len(strokes) == 2:
        return [np.array([BEVEL_L, BEVEL_L_PRIME]), np.array([BEVEL_L_PRIME, BEVEL_L])]
    return []


def choose(
    role_logits: torch.Tensor,
    face_logits: torch.Tensor,
    op: int,
    strokes: list[np.ndarray],
    normal_image: np.ndarray,
    size: int,
) -> Choice:
    """The stroke roles and the base face, read together where the drawing ties them.

    A prism's or sweep's end outline lies from its start outline along n_f, a bevel's l'
    from its l along -n_f (OUTLINES), so in the image the one lies from the other along
    n_f's image, within OUTLINE_SHIFT_COS: the likeliest pair of a face and a labelling
    the drawing allows that agree so is chosen (log-probabilities summed). A face seen
    head-on (its normal's image shorter than MIN_SIN) agrees with any labelling. Where
    the drawing allows no such labelling (an extrusion, not a prism's corner graph) or
    none agrees with any face: `decode_roles` and the likeliest face, each alone.

    Args:
        role_logits: (S, sum(ROLES)) and face_logits: (K, N_CLASSES), the head's
        outputs for one sketch; strokes: its S polylines (pixels); normal_image: (K, 2)
        each face token's normal seen in the image (Tokens.normal_image); size: the
        maps' side (pixels).
    """
    probs = role_probabilities(role_logits, op)
    face_lp = face_logits[: len(normal_image), op].log_softmax(0).numpy()
    alone = Choice(decode_roles(probs, op), int(face_lp.argmax()) if len(face_lp) else -1)
    labellings = _outline_labellings(op, strokes, size)
    if not labellings or not len(face_lp):
        return alone
    labels = np.stack(labellings)  # (L, S)
    role_lp = np.log(np.clip(probs.numpy(), 1e-12, None))
    score = role_lp[np.arange(len(strokes))[None], labels].sum(1)[:, None] + face_lp[None]
    first, second, sign = OUTLINES[LABELLED[op]]
    mids = np.stack([np.asarray(s, float).reshape(-1, 2).mean(0) for s in strokes])
    shift = np.stack(
        [mids[lab == second].mean(0) - mids[lab == first].mean(0) for lab in labels]
    )  # (L, 2)
    n_img = sign * np.asarray(normal_image, np.float64)  # (K, 2)
    n_len = np.linalg.norm(n_img, axis=1)
    cos = shift @ n_img.T / np.maximum(np.linalg.norm(shift, axis=1)[:, None] * n_len, 1e-12)
    agree = (cos > OUTLINE_SHIFT_COS[LABELLED[op]]) | (n_len < MIN_SIN)[None]
    score = np.where(agree, score, -np.inf)  # (L, K)
    if not np.isfinite(score).any():
        return alone
    lab, face = np.unravel_index(int(score.argmax()), score.shape)
    return Choice([int(v) for v in labels[lab]], int(face))
