# SPDX-License-Identifier: LGPL-2.1-or-later
"""A sample's strokes as `interpret` reads them: cut and joined into pieces of curves
(sketch/segment.py), each piece labelled with the role of the curve it draws.

The data set labels a stroke with its first curve's role (`stroke_parts`), which is the
whole truth only for the generator's hand (one stroke per curve). People's hand draws an
outline in one stroke and an edge in two; `interpret` cuts and joins those into pieces
before the head reads them, so the head learns and is scored on the same pieces, each
labelled by the C~ map under its pixels (painted per curve, datagen/hand.py).
"""

from __future__ import annotations

import numpy as np

from Sketch2CADWorkbench.render.strokes import rasterize
from Sketch2CADWorkbench.sketch.segment import segment_strokes


def piece_role(piece: np.ndarray, curve_label: np.ndarray, stroke_mask: np.ndarray) -> int:
    """The commonest C~ label on the stroke pixels under one piece; 0 where it crosses
    none (a gap the segmentation bridged)."""
    h, w = curve_label.shape
    under = (rasterize([piece], w, h) > 0) & (stroke_mask > 0)
    if not under.any():
        return 0
    return int(np.bincount(np.rint(curve_label[under]).astype(np.int64)).argmax())


def sketch_pieces(
    strokes: list, curve_label: np.ndarray, stroke_mask: np.ndarray
) -> tuple[list[np.ndarray], list[int]]:
    """The pieces of one sample's strokes (`segment_strokes`) and each one's role
    (`piece_role`).

    Args:
        strokes: the sample's stroke polylines (pixels of its maps); curve_label: (H, W)
            C~; stroke_mask: (H, W) M~.
    """
    pieces = segment_strokes([np.asarray(s, float) for s in strokes])
    return pieces, [piece_role(q, curve_label, stroke_mask) for q in pieces]
