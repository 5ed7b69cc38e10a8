# SPDX-License-Identifier: LGPL-2.1-or-later
"""A step applied with its mirror image through one of the model's mid-planes."""

from __future__ import annotations

import cadquery as cq
import numpy as np

from ..brep.operators import apply_operation
from ..brep.protocol import EdgeSet, Operation, OperatorType
from ..brep.symmetry import mid_plane, reflect


def apply_with_symmetry(
    solid: cq.Shape, op: Operation, symmetry: str | None, result: cq.Solid | None = None
) -> tuple[tuple[Operation, ...], cq.Solid]:
    """Apply the operation (unless its `result` is given) and, if asked, its mirror image
    through a mid-plane."""
    result = apply_operation(solid, op) if result is None else result
    if symmetry is None:
        return (op,), result
    origin, normal = mid_plane(solid, symmetry)
    mirrored = reflect(op, origin, normal)
    if _rounds_the_same_edge(op, mirrored):
        return (op,), result
    return (op, mirrored), apply_operation(result, mirrored)


def _rounds_the_same_edge(op: Operation, mirrored: Operation) -> bool:
    """A bevel along a whole edge that the mirror plane cuts in half: its image swaps c and
    c' and would round the edge already rounded (the step refuses such a corner); a
    round of a chain or a face's outline whose image is on the same face."""
    if op.type is not OperatorType.BEVEL:
        return False
    if op.across:  # a chain or outline through the mirror plane is its own image
        return op.edges is not EdgeSet.DRAWN and np.allclose(op.face.normal, mirrored.face.normal)
    ends = np.array([op.corner, op.opposite], float)
    image = np.array([mirrored.opposite, mirrored.corner], float)
    return bool(np.allclose(ends, image, rtol=0, atol=1e-9 * max(1.0, float(np.abs(ends).max()))))
