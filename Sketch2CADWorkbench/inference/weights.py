# SPDX-License-Identifier: LGPL-2.1-or-later
"""The shipped network weights, and the predictor that the interpret pipeline calls.

The weights live inside the package (inference/weights/sketch2cad_net.pt, described by
inference/weights/MODEL_CARD.md) and load from disk only: nothing is downloaded. A
structured head (inference/head/) beside a U-Net's file, sketch2cad_head.pt, is loaded
with it; the head records the SHA-256 of the U-Net it was trained on, and a head beside
another U-Net is refused.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import torch

from ..brep.protocol import OperatorType
from ..sketch.labels import CLASSES
from .models import Sketch2CADNet, load_checkpoint

WEIGHTS_DIR = Path(__file__).resolve().parent / "weights"
WEIGHTS_NAME = "sketch2cad_net.pt"
DEFAULT_WEIGHTS = WEIGHTS_DIR / WEIGHTS_NAME
HEAD_NAME = "sketch2cad_head.pt"


def resolve(path: str | Path | None = None) -> Path:
    """The weights file for `path`: a file, a run folder holding WEIGHTS_NAME, or None
    for the shipped weights.

    Raises:
        FileNotFoundError: saying what to do, when there is no such file.
    """
    path = Path(path) if path else DEFAULT_WEIGHTS
    if path.is_dir():
        path = path / WEIGHTS_NAME
    if not path.is_file():
        raise FileNotFoundError(
            f"no network weights at {path}: train them with `sketch2cad train --data DIR "
            f"--out RUN` and pass --weights RUN, or copy RUN/{WEIGHTS_NAME} to {WEIGHTS_DIR}/ "
            "(see the model card there)"
        )
    return path


def load_model(path: str | Path | None = None) -> tuple[Sketch2CADNet, dict]:
    """The network (eval mode, CPU) and its checkpoint dictionary; see `resolve`."""
    return load_checkpoint(resolve(path))


class NetworkPredictor:
    """Classification and segmentation from one forward pass per sketch.

    `classify` runs the network and keeps its outputs; `segment` on the same inputs
    array reuses them, so the interpret pipeline pays for one pass.
    """

    def __init__(self, model: Sketch2CADNet, threads: int | None = 2):
        self.model = model.fused()  # an inference copy: batch norms folded, eval mode
        self.threads = threads
        self._inputs: np.ndarray | None = None  # held, so identity means the same sketch
        self._out: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None

    def _run(self, inputs: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        if inputs is not self._inputs:
            if self.threads:
                torch.set_num_threads(self.threads)
            x = torch.from_numpy(np.ascontiguousarray(inputs, dtype=np.float32))[None]
            probs, f, c = self.model.predict(x)
            self._out = (probs[0].numpy(), f[0].numpy(), c[0].numpy())
            self._inputs = inputs
        return self._out

    def classify(self, inputs: np.ndarray) -> np.ndarray:
        """(5, H, W) S, D, N -> (4,) probabilities in OperatorType order."""
        return self._run(inputs)[0]

    def segment(self, inputs: np.ndarray, op_type: OperatorType) -> tuple[np.ndarray, np.ndarray]:
        """(5, H, W) -> the operator's F (H, W) probabilities and C (H, W) curve values."""
        _, f, c = self._run(inputs)
        k = CLASSES.index(op_type)
        return f[k], c[k]


def shipped_head(path: str | Path | None = None) -> Path | None:
    """The structured head lying beside the weights file of `path` (see `resolve`), if any."""
    head = resolve(path).parent / HEAD_NAME
    return head if head.is_file() else None


def load_predictor(path: str | Path | None = None, structured: bool = True) -> NetworkPredictor:
    """The predictor for a weights file or run folder (default: the shipped weights):
    with the structured head when HEAD_NAME lies beside the weights file (and
    `structured`), else the U-Net alone.

    Raises:
        ValueError: the head beside the weights was trained on another U-Net.
    """
    unet = resolve(path)
    head = shipped_head(path)
    if structured and head is not None:
        from .head.predictor import load_structured_predictor  # it builds on this module

        return load_structured_predictor(head, unet)
    model, _ = load_model(unet)
    return NetworkPredictor(model)
