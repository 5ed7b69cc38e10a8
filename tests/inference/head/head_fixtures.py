# SPDX-License-Identifier: LGPL-2.1-or-later
"""A small scene of two faces and three strokes for the structured head's tests."""

import numpy as np
import torch

from Sketch2CADWorkbench.inference.head.tokens import feature_maps, tokens

SIZE = 32


def scene():
    """Two faces side by side (IDs 3 and 7), three strokes, random-weights maps."""
    face_id = np.full((SIZE, SIZE), -1, np.int16)
    face_id[4:28, 4:16] = 3
    face_id[4:28, 16:28] = 7
    strokes = [
        np.array([[6.0, 8.0], [14.0, 8.0]]),
        np.array([[6.0, 8.0], [6.0, 24.0]]),
        np.array([[20.0, 10.0], [26.0, 20.0], [21.0, 25.0]]),
    ]
    return face_id, strokes


def scene_tokens(net, strokes, face_id):
    """The tokens of `strokes` over `face_id`, the U-Net `net` reading fixed random inputs."""
    x = torch.rand(1, 5, SIZE, SIZE, generator=torch.Generator().manual_seed(1))
    with torch.no_grad():
        u = feature_maps(net, x)
    return tokens(u.logits[0], u.sketch(0), strokes, face_id)
