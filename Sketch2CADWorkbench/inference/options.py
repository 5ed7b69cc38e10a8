# SPDX-License-Identifier: LGPL-2.1-or-later
"""The designer's choices for one sketch step (stored in sessions, read by interpret)."""

from __future__ import annotations

from dataclasses import dataclass

from ..brep.protocol import EdgeSet, Mode
from .fitting.regularize import SNAP_PX


@dataclass(frozen=True)
class InterpretOptions:
    """Regularization (snap and rectify), a forced Boolean option, a mirror plane.

    With `regularize`, values snap to targets within `snap_px` pixels of the view the
    strokes were drawn in (farther when the strokes miss their reading by more:
    `fitting.regularize.hand_tolerance`) and lengths to multiples of `snap_step` mm
    (0: no grid);
    `skip_snaps` names snaps the designer undid (keys of
    inference.fitting.regularize.SNAP_KINDS). `edges` is which edges a bevel drawn across
    an edge follows: that edge, its tangent chain, or the whole outline of its face.
    """

    regularize: bool = True
    option: Mode | None = None
    symmetry: str | None = None  # "x", "y" or "z": mirror through the model's mid-plane
    snap_step: float = 0.0
    snap_px: float = SNAP_PX
    skip_snaps: frozenset[str] = frozenset()
    # Read pieces of curves, not whole strokes (sketch/segment.py); off only to measure
    # what that stage gains.
    segment: bool = True
    edges: EdgeSet = EdgeSet.DRAWN
