# SPDX-License-Identifier: LGPL-2.1-or-later
"""The paper's network metrics (Sec. 6, Tables 1-2), on a data set the networks were not
trained on, all at the full 256 x 256 size that the fitting stage reads:

classification accuracy
    argmax of the class probabilities against the ground-truth operator, over all
    samples; the confusion matrix has rows = truth, columns = prediction.
face IoU (per operator)
    for each sample of that (ground-truth) operator, with F the base-face map of the
    ground-truth operator's head (the paper evaluates each segmentation network on its
    own operator, whatever the classifier says):
        P = {F > 0.5}, G = {F~ > 0.5},  IoU = |P and G| / |P or G|  (1 when both are empty),
    then the mean over the samples. `face_iou_pooled` adds sum |P and G| / sum |P or G|.
curve accuracy (per operator)
    the predicted class of a stroke pixel is the number of thresholds its C exceeds
    (0.5 for extrude and bevel; 0.5 and 1.5 for add/sub and sweep, as the paper's
    C > 0.5 / C <= 0.5 split); the accuracy is the fraction of all stroke pixels (M~)
    of that operator's samples whose class equals C~. `curve_accuracy_per_sample` adds
    the mean of the per-sample fractions.
latency
    the median wall time of `predict` (pooling, network, upsampling of every output to
    256 x 256) on one sketch (batch 1) at 2 threads, over the first samples.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import torch

from Sketch2CADWorkbench.sketch.labels import CURVE_THRESHOLDS, LABELLED

# Every operator a sample may be labelled with: the U-Net's four classes and the shell,
# which only the structured head classifies.
NAMES = [c.value for c in LABELLED]
# Curve class thresholds per operator index; a pixel's class = how many its C exceeds.
THRESHOLDS = torch.tensor([CURVE_THRESHOLDS[c] for c in LABELLED])
# The paper's figures for its networks at level-1 noise: Table 1 ("ours"), face IoU and
# curve accuracy per operator, and the classification accuracy its text gives beside it.
PAPER_TABLE_1: dict[str, Any] = {
    "classification_accuracy": 0.9979,
    "face_iou": {"extrude": 0.9178, "bevel": 0.9173, "addsub": 0.7826, "sweep": 0.7834},
    "curve_accuracy": {"extrude": 0.9804, "bevel": 0.9812, "addsub": 0.9354, "sweep": 0.9557},
}


def face_overlap(
    face_prob: torch.Tensor, face_label: torch.Tensor
) -> tuple[torch.Tensor, torch.Tensor]:
    """|P and G| and |P or G| per sample, P = {F > 0.5}, G = {F~ > 0.5}.

    Args:
        face_prob: (B, H, W) predicted F in 0..1; face_label: (B, H, W) F~.
    Returns:
        intersection and union pixel counts, (B,) int64 each.
    """
    p, g = face_prob > 0.5, face_label > 0.5
    return (p & g).sum((1, 2)), (p | g).sum((1, 2))


def face_iou(face_prob: torch.Tensor, face_label: torch.Tensor) -> torch.Tensor:
    """(B,) IoU of {F > 0.5} and {F~ > 0.5}; 1 where both are empty."""
    inter, union = face_overlap(face_prob, face_label)
    return torch.where(union > 0, inter / union.clamp(min=1), 1.0)


def curve_classes(curve: torch.Tensor, op: torch.Tensor) -> torch.Tensor:
    """(B, H, W) C values -> (B, H, W) int64 classes under operator op's thresholds (B,)."""
    t = THRESHOLDS.to(curve.device)[op]  # (B, 2)
    return (curve[:, None] > t[:, :, None, None]).sum(1)


def curve_hits(
    curve: torch.Tensor, curve_label: torch.Tensor, stroke_mask: torch.Tensor, op: torch.Tensor
) -> tuple[torch.Tensor, torch.Tensor]:
    """Stroke pixels whose predicted class equals C~, and all stroke pixels, per sample.

    Args:
        curve: (B, H, W) predicted C; curve_label: (B, H, W) C~; stroke_mask: (B, H, W) M~;
        op: (B,) the operator whose encoding C uses.
    Returns:
        (B,) int64 correct counts and (B,) int64 stroke pixel counts.
    """
    m = stroke_mask > 0.5
    right = (curve_classes(curve, op) == curve_label.round().long()) & m
    return right.sum((1, 2)), m.sum((1, 2))


@dataclass
class Tally:
    """Per-sample results, summed up into the metrics' JSON (`summary`)."""

    rows: list[torch.Tensor] = field(default_factory=list)

    def add(self, op, pred, noise, inter, union, right, strokes) -> None:
        """Each argument (B,): truth, predicted class, noise level, face intersection and
        union, correct and total stroke pixels."""
        self.rows.append(
            torch.stack(
                [
                    torch.as_tensor(v).long().cpu()
                    for v in (op, pred, noise, inter, union, right, strokes)
                ],
                1,
            )
        )

    def summary(self) -> dict:
        r = torch.cat(self.rows) if self.rows else torch.zeros(0, 7, dtype=torch.long)
        op, pred, noise, inter, union, right, strokes = r.T
        confusion = torch.zeros(len(NAMES), len(NAMES), dtype=torch.long)
        confusion.index_put_((op, pred), torch.ones_like(op), accumulate=True)
        iou = torch.where(union > 0, inter / union.clamp(min=1), 1.0)
        frac = torch.where(strokes > 0, right / strokes.clamp(min=1), 1.0)

        def group(sel: torch.Tensor) -> dict:
            k = int(sel.sum())
            if not k:
                return {"n": 0, "face_iou": None, "curve_accuracy": None}
            return {
                "n": k,
                "face_iou": float(iou[sel].mean()),
                "curve_accuracy": float(right[sel].sum() / strokes[sel].sum().clamp(min=1)),
                "face_iou_pooled": float(inter[sel].sum() / union[sel].sum().clamp(min=1)),
                "curve_accuracy_per_sample": float(frac[sel].mean()),
            }

        def accuracy(sel: torch.Tensor) -> float | None:
            return float((op[sel] == pred[sel]).float().mean()) if sel.any() else None

        levels = sorted(int(v) for v in noise.unique())
        return {
            "n": len(op),
            "classification_accuracy": accuracy(torch.ones_like(op, dtype=torch.bool)),
            "per_operator": {name: group(op == k) for k, name in enumerate(NAMES)},
            "confusion_matrix": {"classes": NAMES, "rows_true_cols_predicted": confusion.tolist()},
            "per_noise_level": {
                str(lv): {
                    "classification_accuracy": accuracy(noise == lv),
                    **{name: group((noise == lv) & (op == k)) for k, name in enumerate(NAMES)},
                }
                for lv in levels
            },
        }
