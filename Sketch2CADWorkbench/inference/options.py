# SPDX-License-Identifier: LGPL-2.1-or-later
"""The designer's choices for one sketch step (stored in sessions, read by interpret)."""
from __future__ import annotations

from dataclasses import dataclass

from ..brep.protocol import Mode


@dataclass(frozen=True)
class InterpretOptions:
    """Regularization (snap and rectify), a forced Boolean option, a mirror plane."""

    regularize: bool = True
    option: Mode | None = None
    symmetry: str | None = None  # "x", "y" or "z": mirror through the model's mid-plane
