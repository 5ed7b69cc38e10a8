# SPDX-License-Identifier: LGPL-2.1-or-later
"""One training/evaluation sample: the network inputs, the labels, and the ground truth.

This is the contract between data generation, training, evaluation and the
interpret pipeline. Maps are H x W (256 x 256 by default) in the camera's pixel
convention (see render/camera.py).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from Sketch2CADWorkbench.brep.protocol import Operation, OperatorType, Protocol
from Sketch2CADWorkbench.render.camera import OrthoCamera


@dataclass
class Sample:
    """A sketch over a context model, with its labels.

    Inputs:
        sketch: (H, W) float32 in {0, 1}, the stroke map S.
        depth: (H, W) float32, D: farthest foreground 0, closest 1, background 0.
        normal: (3, H, W) float32, N: camera-space normal + (1, 1, 1), background 0.
    Labels:
        op_type: the operator of the last operation.
        face_id: (H, W) int32, which B-rep face each pixel sees (-1 background); the
            index is into `context solid`.Faces().
        face_label: (H, W) float32 in {0, 1}, F~: pixels of the base face f.
        curve_label: (H, W) float32, C~ with the per-operator encoding of
            Sketch2CADWorkbench/sketch/labels.py (0 off strokes).
        stroke_mask: (H, W) float32 in {0, 1}, M~: the stroke pixels.
    Ground truth, for end-to-end evaluation:
        context: the protocol before the last operation; operation: the last operation.
        camera: the view; strokes: the raw 2D polylines (pixels), one (K, 2) array each;
        stroke_parts: the curve label of each stroke; noise_level: 1, 2 or 3.
    """

    op_type: OperatorType
    sketch: np.ndarray
    depth: np.ndarray
    normal: np.ndarray
    face_id: np.ndarray
    face_label: np.ndarray
    curve_label: np.ndarray
    stroke_mask: np.ndarray
    context: Protocol
    operation: Operation
    camera: OrthoCamera
    strokes: list[np.ndarray]
    stroke_parts: list[int]
    noise_level: int = 1

    def inputs(self) -> np.ndarray:
        """The (5, H, W) float32 network input: S, D, N stacked."""
        return np.concatenate([self.sketch[None], self.depth[None], self.normal]).astype(np.float32)
