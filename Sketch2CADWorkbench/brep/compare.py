# SPDX-License-Identifier: LGPL-2.1-or-later
"""Comparing solids: the volume IoU used by the end-to-end recovery rate."""
from __future__ import annotations

import cadquery as cq


def volume_iou(a: cq.Shape, b: cq.Shape) -> float:
    """|A and B| / |A or B| by exact Booleans, in 0..1 (1 for identical solids).

    |A or B| is computed as |A| + |B| - |A and B|, which needs one Boolean, not two.
    """
    common = a.intersect(b).Volume()
    union = a.Volume() + b.Volume() - common
    return float(common / union) if union > 0 else 0.0
