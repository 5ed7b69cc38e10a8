# SPDX-License-Identifier: LGPL-2.1-or-later
"""The shipped network weights and the predictor the interpret pipeline calls."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import torch

from ..brep.protocol import OperatorType
from .models import Sketch2CADNet, load_model

WEIGHTS_DIR = Path(__file__).resolve().parent / "weights"
DEFAULT_WEIGHTS = WEIGHTS_DIR / "sketch2cad_net.pt"
CLASSES = list(OperatorType)


class NetworkPredictor:
    """Classification and segmentation from one forward pass per sketch.

    `classify` runs the network and keeps its outputs; `segment` on the same inputs
    reuses them, so the interpret pipeline pays for one pass.
    """

    def __init__(self, model: Sketch2CADNet, threads: int | None = 2):
        self.model = model.eval()
        self.threads = threads
        self._inputs: np.ndarray | None = None  # held, so identity means the same sketch
        self._out: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None

    def _run(self, inputs: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        if inputs is not self._inputs:
            if self.threads:
                torch.set_num_threads(self.threads)
            probs, f, c = self.model.predict(torch.from_numpy(np.ascontiguousarray(inputs))[None])
            self._out = (probs[0].numpy(), f[0].numpy(), c[0].numpy())
            self._inputs = inputs
        return self._out

    def classify(self, inputs: np.ndarray) -> np.ndarray:
        """(5, H, W) -> (4,) probabilities in OperatorType order."""
        return self._run(inputs)[0]

    def segment(self, inputs: np.ndarray, op_type: OperatorType) -> tuple[np.ndarray, np.ndarray]:
        """(5, H, W) -> the operator's F (H, W) probability and C (H, W) curve map."""
        _, f, c = self._run(inputs)
        k = CLASSES.index(op_type)
        return f[k], c[k]


def load_predictor(path: str | Path | None = None) -> NetworkPredictor:
    """The predictor for a weights file (default: the weights shipped in the package).

    Raises:
        FileNotFoundError: with what to do, when there are no weights at `path`.
    """
    path = Path(path) if path else DEFAULT_WEIGHTS
    if path.is_dir():
        path = path / DEFAULT_WEIGHTS.name
    if not path.exists():
        raise FileNotFoundError(f"no network weights at {path}; train them with "
                                "`sketch2cad train` (see the model card) or pass --weights")
    model, _ = load_model(path)
    return NetworkPredictor(model)
