# SPDX-License-Identifier: LGPL-2.1-or-later
"""The interpret pipeline's Predictor with the structured head's choices in F and C."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import torch

from ...brep.protocol import OperatorType
from ...sketch.labels import LABELLED
from ..models import Sketch2CADNet, load_checkpoint
from ..weights import NetworkPredictor, resolve
from .checkpoint import load_head, sha256_of
from .decode import role_probabilities
from .model import StructureHead, collate
from .paint import painted
from .tokens import feature_maps, tokens


class StructuredPredictor(NetworkPredictor):
    """The interpret pipeline's Predictor with the head's choices in F and C.

    `observe(strokes, face_id)` hands over the structures of the sketch about to be
    classified (the context camera's stroke polylines and face-ID map: context.py's
    Context.strokes and Context.maps.face_id); `classify` and `segment` then answer with
    the head's class probabilities and the painted maps, and `stroke_roles` and
    `face_probabilities` expose the per-stroke and per-face probabilities behind them.
    The first inputs after `observe` are taken as that sketch's; without `observe`, or
    for other inputs after them, it answers as the plain U-Net predictor.
    """

    def __init__(self, model: Sketch2CADNet, head: StructureHead, threads: int | None = 2):
        super().__init__(model, threads)
        self.head = head.eval()
        self._strokes: list[np.ndarray] | None = None
        self._face_id: np.ndarray | None = None
        self._head_out = None  # (inputs, tokens, class probs, role logits, face logits)

    def observe(self, strokes: list[np.ndarray], face_id: np.ndarray) -> None:
        """The next sketch's stroke polylines (pixels of the maps) and face-ID map."""
        self._strokes = [np.asarray(s, float) for s in strokes]
        self._face_id = np.asarray(face_id)
        self._head_out = None

    def _structured(self, inputs: np.ndarray):
        if self._strokes is None:
            return None
        if self._head_out is not None and self._head_out[0] is not inputs:
            return None  # another sketch's inputs than the observed one: the U-Net alone
        if self._head_out is None:  # the first inputs since `observe` are its sketch's
            if self.threads:
                torch.set_num_threads(self.threads)
            x = torch.from_numpy(np.ascontiguousarray(inputs, dtype=np.float32))[None]
            with torch.inference_mode():  # the model is in eval mode since __init__
                u = feature_maps(self.model, x)
                t = tokens(u.logits[0], u.sketch(0), self._strokes, self._face_id)
                cls, roles, faces = self.head(*collate([t]))
            self._head_out = (inputs, t, cls[0].softmax(0).numpy(), roles[0], faces[0])
        return self._head_out

    def classify(self, inputs: np.ndarray) -> np.ndarray:
        out = self._structured(inputs)
        return super().classify(inputs) if out is None else out[2]

    def stroke_roles(self, inputs: np.ndarray, op_type: OperatorType) -> np.ndarray:
        """(S, roles) probabilities of each observed stroke's role under op_type, in the
        curve label order of sketch/labels.py."""
        out = self._structured(inputs)
        if out is None:
            raise ValueError("stroke_roles needs observe(strokes, face_id) first")
        return role_probabilities(out[3], LABELLED.index(op_type)).numpy()

    def face_probabilities(self, inputs: np.ndarray, op_type: OperatorType) -> dict[int, float]:
        """Face-ID -> probability of being the base face under op_type (visible faces)."""
        out = self._structured(inputs)
        if out is None:
            raise ValueError("face_probabilities needs observe(strokes, face_id) first")
        p = out[4][:, LABELLED.index(op_type)].softmax(0)
        return {int(i): float(v) for i, v in zip(out[1].face_ids, p, strict=False)}

    def segment(self, inputs: np.ndarray, op_type: OperatorType) -> tuple[np.ndarray, np.ndarray]:
        out = self._structured(inputs)
        if out is None:
            return super().segment(inputs, op_type)
        k = LABELLED.index(op_type)
        return painted(out[3], out[4], k, self._strokes, out[1], self._face_id)


def load_structured_predictor(
    head_path: str | Path, weights: str | Path | None = None
) -> StructuredPredictor:
    """The U-Net of `weights` (default: shipped) with the head of `head_path`.

    Raises:
        ValueError: the head was trained on another U-Net's features (or does not say
            on which: it records the U-Net's SHA-256).
    """
    path = resolve(weights)
    model, _ = load_checkpoint(path)
    head, ckpt = load_head(head_path)
    # the head reads the U-Net's inner features, which another U-Net lays out otherwise
    if ckpt.get("unet_sha256") != sha256_of(path):
        raise ValueError(
            f"{head_path} was trained on the features of another U-Net "
            f"({ckpt.get('unet')}), not {path}"
        )
    return StructuredPredictor(model, head)
