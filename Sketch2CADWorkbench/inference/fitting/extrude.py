# SPDX-License-Identifier: LGPL-2.1-or-later
"""Extrude regression: the offset d of face f by line search (paper, "Extrude regression")."""
from __future__ import annotations

import cadquery as cq
import numpy as np

from ...brep.faces import FaceFrame, face_ref_of, model_scale
from ...brep.protocol import Extrude
from ...render.camera import OrthoCamera
from .common import (
    DistanceField,
    FitError,
    edge_samples,
    line_search,
    search_range,
    stroke_pixels,
)

# Mean distance (px) between the moved face's edges and the offset strokes above which
# the strokes are not read as an extrusion of f.
MAX_MISMATCH_PX = 12.0
# Samples along f's edges at most (one per context pixel below that): the line search
# scores every candidate offset at every sample, so a face far larger than the context
# (its edges run far out of the frame) must not multiply its cost.
MAX_EDGE_SAMPLES = 4096
# Views closer than this to head-on (|cos| of the angle between n_f and the view) show
# no extrusion depth.
HEAD_ON_COS = 0.995


def fit_extrude(solid: cq.Shape, face: cq.Face, camera: OrthoCamera,
                offset_strokes: list[np.ndarray],
                profile_strokes: list[np.ndarray] | None = None) -> Extrude:
    """Find d such that the edges of f moved by d * n_f match the offset-curve strokes.

    The paper matches the moved edges to the offset curve only; when side-edge strokes
    are given, the side edges from f's corners to the moved corners are matched to them
    too, which halves the effect of endpoint noise on d.

    Args:
        solid: the context solid (sets the search range: -1.5..1.5 model diagonals,
            step 0.0075 diagonal, as in the paper).
        face: the base face f (planar).
        camera: the context camera; strokes are in its pixels.
        offset_strokes: the strokes classified as the offset curve (C > 0.5).
        profile_strokes: the strokes classified as side edges (C <= 0.5), if any.
    Raises:
        FitError: no offset strokes, a head-on view, or no offset matches the strokes.
    Returns:
        The Extrude operation on f.
    """
    if not offset_strokes:
        raise FitError("extrude: no stroke was recognised as the moved face's outline")
    frame = FaceFrame.of(face)
    if abs(float(frame.normal @ camera.basis()[2])) > HEAD_ON_COS:
        raise FitError("extrude: the face is seen head-on, so its offset cannot be read; "
                       "turn the view")
    scale = model_scale(solid)
    field = DistanceField(stroke_pixels(offset_strokes, (camera.height, camera.width)))
    perimeter = sum(e.Length() for e in face.Edges())
    points = edge_samples(face, spacing=max(camera.pixel_size, perimeter / MAX_EDGE_SAMPLES))
    cands = search_range(scale)
    cands = cands[np.abs(cands) > 1e-9]  # d = 0 is no operation
    sides = None
    if profile_strokes:
        corners = np.array([v.toTuple() for v in face.Vertices()])
        sides = (corners, DistanceField(stroke_pixels(profile_strokes,
                                                       (camera.height, camera.width))))
    d, err = line_search(points, frame.normal, camera, field, cands, sides)
    if err > MAX_MISMATCH_PX:
        raise FitError(f"extrude: no offset of the face matches the strokes (closest is "
                       f"{err:.1f} px off on average)")
    if abs(d) < 1e-6 * scale:
        raise FitError("extrude: the strokes lie on the face itself (offset 0)")
    return Extrude(face_ref_of(face), float(d))
