# SPDX-License-Identifier: LGPL-2.1-or-later
"""The base face f by counting (paper, "Operator regression")."""
from __future__ import annotations

import cadquery as cq
import numpy as np

from .common import FitError


def select_base_face(face_prob: np.ndarray, face_id: np.ndarray, solid: cq.Shape) -> cq.Face:
    """The planar face seen by the most pixels of the binarised face map.

    f* = argmax_i sum over pixels with Id = f_i of [F > 0.5].

    Args:
        face_prob: (H, W) predicted base-face probability F.
        face_id: (H, W) rendered face indices into solid.Faces() (-1 background).
        solid: the context solid.
    Raises:
        FitError: no face pixel is predicted, or the winner is not planar.
    """
    ids = face_id[(face_prob > 0.5) & (face_id >= 0)]
    if ids.size == 0:
        raise FitError("no face of the model was recognised under the sketch; draw on a "
                       "visible face")
    index = int(np.bincount(ids).argmax())
    face = solid.Faces()[index]
    if face.geomType() != "PLANE":
        raise FitError("the sketch stands on a curved face; operations need a planar face")
    return face
