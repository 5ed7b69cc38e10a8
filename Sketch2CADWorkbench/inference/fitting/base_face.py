# SPDX-License-Identifier: LGPL-2.1-or-later
"""The base face f by counting (paper, "Operator regression")."""

from __future__ import annotations

import cadquery as cq
import numpy as np

from ...brep.faces import CURVED_GEOM_TYPES, face_kinds
from .common import FitError, resample, sample_map

MIN_PIXELS = 20
# Share of a stroke's samples that must fall on one face for the stroke to lie on it.
ON_FACE_SHARE = 0.6


def rank_base_faces(
    face_prob: np.ndarray, face_id: np.ndarray, solid: cq.Shape, curved: bool = False
) -> list[int]:
    """Planar faces in view, best first, by the paper's counting of the face map.

    Rank by sum over pixels with Id = f_i of [F > 0.5] (the paper's f* is the first),
    then, for faces no such pixel falls on, by the mean F over their visible pixels
    (among faces of at least MIN_PIXELS pixels): an unsure network still orders them.
    Only planar faces count unless `curved` (an operator that stands on a cylinder's or
    cone's side too: extrusions, prisms and sweeps), and even then a curved face counts only by its
    F > 0.5 pixels: it is often both large and next to the base face, and an unsure F
    would otherwise put it first.

    Args:
        face_prob: (H, W) predicted base-face probability F.
        face_id: (H, W) rendered face indices into solid.Faces() (-1 background).
        solid: the context solid.
        curved: cylinders' and cones' sides may be the base face.
    Returns:
        Indices into solid.Faces().
    Raises:
        FitError: no face that may be the base face in view.
    """
    faces = face_kinds(solid)
    kinds = CURVED_GEOM_TYPES + ("PLANE",) if curved else ("PLANE",)
    planar = np.array([f == "PLANE" for f in faces] + [False])
    usable = np.array([f in kinds for f in faces] + [False])
    seen = face_id >= 0
    if not seen.any():
        raise FitError("the model is not in view under the sketch; draw over the model")
    index = np.where(seen, face_id, len(faces))
    seen_usable, seen = seen & usable[index], seen & planar[index]
    if not seen_usable.any():
        raise FitError("the sketch stands on a curved face; operations need a planar face")
    n = len(faces)
    votes = np.bincount(face_id[(face_prob > 0.5) & seen_usable], minlength=n)
    pixels = np.bincount(face_id[seen], minlength=n)
    mean = np.bincount(face_id[seen], weights=face_prob[seen], minlength=n) / np.maximum(pixels, 1)
    order = sorted(range(n), key=lambda i: (-votes[i], -mean[i]))
    return [i for i in order if votes[i] > 0 or pixels[i] >= MIN_PIXELS]


def select_base_face(face_prob: np.ndarray, face_id: np.ndarray, solid: cq.Shape) -> cq.Face:
    """The paper's f*: the planar face seen by the most pixels of the binarised F (see
    rank_base_faces).

    Raises:
        FitError: no planar face in view, or none recognised.
    """
    ranked = rank_base_faces(face_prob, face_id, solid)
    if not ranked:
        raise FitError(
            "no face of the model was recognised under the sketch; draw on a visible face"
        )
    return solid.Faces()[ranked[0]]


def face_under_stroke(stroke: np.ndarray, face_id: np.ndarray) -> int | None:
    """The index of the face that most of a stroke's samples fall on, if most of them
    (ON_FACE_SHARE) fall on one face; None otherwise (a stroke in the air or on an edge).
    """
    return face_under_strokes([stroke], face_id)


def face_under_strokes(strokes: list[np.ndarray], face_id: np.ndarray) -> int | None:
    """The face that most of the strokes' samples, pooled, fall on, if ON_FACE_SHARE of
    them do; None otherwise. Pooled, one side of an outline that a hand drew off its face
    (past a thin wall's edge, onto the next face) does not hide the face the others lie on.
    """
    counts, samples = _face_counts(strokes, face_id)
    if not counts.size:
        return None
    best = int(counts.argmax())
    return best if counts[best] >= ON_FACE_SHARE * samples else None


def face_most_under(strokes: list[np.ndarray], face_id: np.ndarray) -> int | None:
    """The face that more of the strokes' samples on the model fall on than any other;
    None when none of them falls on the model."""
    counts, _ = _face_counts(strokes, face_id)
    return int(counts.argmax()) if counts.size else None


def _face_counts(strokes: list[np.ndarray], face_id: np.ndarray) -> tuple[np.ndarray, int]:
    """How many of the strokes' samples fall on each face (by index), and of how many."""
    ids = np.concatenate([sample_map(face_id, resample(s)).astype(int) for s in strokes])
    return np.bincount(ids[ids >= 0]), len(ids)
