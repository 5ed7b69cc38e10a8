# SPDX-License-Identifier: LGPL-2.1-or-later
"""Bevel regression: profile l, corner c and opposite corner c' (paper, "Bevel regression")."""

from __future__ import annotations

from dataclasses import dataclass

import cadquery as cq
import numpy as np

from ...brep.corners import crease_end, line_edges
from ...brep.faces import FaceFrame, face_ref_of, model_scale
from ...brep.protocol import Bevel
from ...render.camera import OrthoCamera
from .common import FitError, fit_bezier, resample
from .refine import EDGE_MARGIN, BevelImage, refine_bevel

# How far (relative to the image diagonal) a profile stroke's end may lie from an edge
# of f in the image: the hand's error lives in the image (at level 3 about 10 px per axis
# and end, datagen/strokes.py), where back-projected onto a plane seen at a slant it grows
# by 1 / cos (a tolerance in mm of the model refused 11 of 140 held-out level-3 bevels).
EDGE_TOL = 0.08
# How far along each side of the parallelogram that c and l's ends span an inner
# control point may lie (`_inside_corner`): at 1 it could sit on an end, where l has no
# tangent and OCCT builds no cut (held-out level-1 sample 327 of heldout-l1c); the data
# generator's profiles keep theirs within 0.87 (datagen/operations.py `bevel_profile`).
INNER_SPAN = 0.9


def _corner_for(
    ends: np.ndarray, edges, camera: OrthoCamera, scale: float
) -> tuple[np.ndarray, tuple[float, float], tuple]:
    """The corner c of f whose two edges best hold the stroke's two ends, in the image.

    For every vertex shared by two straight edges of f, each stroke end (pixels; (2, 2),
    first and last) is put on the nearer of the two edges' images (the other end on the
    other edge); the corner with the smallest total distance in pixels wins. Returns c,
    where on its edge each end lies (0 at the edge's first point, 1 at its last: the same
    in the image and in 3D, projection being affine) and the two edges ((first, last)
    points), the first stroke end's first.
    """
    best = None
    for i, (a0, a1) in enumerate(edges):
        for _j, (b0, b1) in enumerate(edges[i + 1 :], i + 1):
            for p in (a0, a1):
                for q in (b0, b1):
                    if np.linalg.norm(p - q) > 1e-6 * scale:
                        continue
                    ea, eb = (a0, a1), (b0, b1)
                    for first, second in ((ea, eb), (eb, ea)):
                        ta, da = _on_segment(ends[0], *camera.project(np.stack(first))[0])
                        tb, db = _on_segment(ends[1], *camera.project(np.stack(second))[0])
                        if best is None or da + db < best[0]:
                            best = (da + db, p, (ta, tb), (first, second))
    if best is None:
        raise FitError("bevel: the face has no corner between two straight edges")
    if best[0] > 2 * EDGE_TOL * float(np.hypot(camera.width, camera.height)):
        raise FitError("bevel: the profile stroke must run from one edge of the face to another")
    return best[1], best[2], best[3]


def _on_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> tuple[float, float]:
    """Where on segment a-b (0 at a, 1 at b; kept off the ends) the point nearest to p
    lies, and its distance from p."""
    ab = b - a
    t = float(np.clip((p - a) @ ab / max(float(ab @ ab), 1e-12), EDGE_MARGIN, 1 - EDGE_MARGIN))
    return t, float(np.linalg.norm(p - (a + t * ab)))


def _inside_corner(ctrl: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Move inner control points into the parallelogram that corner c and l's two ends
    span (2D, face frame): c + s (l(0) - c) + t (l(1) - c) with s, t in [0, INNER_SPAN].

    A noisy stroke can make l bulge past an edge of f (s or t < 0: the bevel would not
    build) or swing past its own ends (s or t > 1: the level-3 fits that cut away half
    the face); a designer's round, chamfer or cove has its control polygon in there,
    as the data generator draws them (datagen/operations.py `bevel_profile`), and the
    convex hull property keeps the whole curve in with it.
    """
    out = ctrl.copy()
    axes = np.stack([ctrl[0] - c, ctrl[3] - c], 1)  # (2, 2)
    if abs(np.linalg.det(axes)) < 1e-12 * max(float(np.abs(axes).max()), 1e-12) ** 2:
        return out  # ends in line with c: no parallelogram (place_bevel refuses it)
    st = np.clip(np.linalg.solve(axes, (ctrl[1:3] - c).T), 0.0, INNER_SPAN)  # (2, 2): s, t
    out[1:3] = c + (axes @ st).T
    return out


@dataclass(frozen=True, eq=False)
class BevelFit:
    """A bevel read from its profile stroke, before the refinement of l against all the
    strokes (`refine.refine_bevel`)."""

    operation: Bevel  # as fitted, unrefined
    image: BevelImage  # how l and l' move in the image with its parameters
    x: np.ndarray  # (6,) the parameters as fitted
    frame: FaceFrame  # f's frame, in which l is fitted

    def refined(self, strokes: list[np.ndarray]) -> Bevel:
        """The operation with l's ends (along their edges) and inner control points
        refined so that l and l' lie closest to `strokes` (every stroke of the bevel)."""
        op = self.operation
        ctrl2 = self.image.control(refine_bevel(self.image, self.x, strokes))
        corner = self.frame.to_2d(np.asarray(op.corner, float))[0]
        ctrl = self.frame.to_3d(_inside_corner(ctrl2, corner))
        return Bevel(op.face, op.corner, op.opposite, tuple(tuple(map(float, p)) for p in ctrl))


def fit_bevel(
    solid: cq.Shape, face: cq.Face, camera: OrthoCamera, profile_stroke: np.ndarray
) -> Bevel:
    """Fit l as a cubic Bezier to the profile stroke back-projected onto f's plane:
    `bevel_fit`'s operation. Same arguments and errors."""
    return bevel_fit(solid, face, camera, profile_stroke).operation


def bevel_fit(
    solid: cq.Shape, face: cq.Face, camera: OrthoCamera, profile_stroke: np.ndarray
) -> BevelFit:
    """Fit l as a cubic Bezier to the profile stroke back-projected onto f's plane, up to
    the refinement against all the strokes.

    Args:
        solid: the context solid.
        face: the base face f.
        camera: the context camera; the stroke is in its pixels.
        profile_stroke: the stroke s* with the most l votes (C > 0.5), (K, 2).
    Raises:
        FitError: the stroke's ends do not land on two edges of f that meet at a
            corner, or that corner has no crease along -n_f.
    Returns:
        The fit: its Bevel on f with corner c where l's two edges meet, unrefined.
    """
    frame = FaceFrame.of(face)
    scale = model_scale(solid)
    try:
        pts = camera.back_project_to_plane(resample(profile_stroke), frame.origin, frame.normal)
    except ValueError as e:
        raise FitError(f"bevel: {e}") from None
    stroke = np.asarray(profile_stroke, float).reshape(-1, 2)
    corner, at, edges = _corner_for(stroke[[0, -1]], line_edges(face), camera, scale)
    opposite = crease_end(solid, corner, frame.normal, 1e-6 * scale)
    if opposite is None:
        raise FitError(
            "bevel: the corner has no edge running into the solid along the face "
            "normal, so there is no crease to round"
        )
    (a0, a1), (b0, b1) = (frame.to_2d(np.stack(e)) for e in edges)
    ctrl2 = fit_bezier(
        frame.to_2d(pts),
        a0 + at[0] * (a1 - a0),
        b0 + at[1] * (b1 - b0),
        corner=frame.to_2d(corner)[0],
        span=INNER_SPAN,
    )
    op = Bevel(
        face_ref_of(face),
        tuple(map(float, corner)),
        tuple(map(float, opposite)),
        tuple(tuple(map(float, p)) for p in frame.to_3d(ctrl2)),
    )
    origin = camera.project(frame.origin[None])[0][0]
    image = BevelImage(
        origin,
        np.stack([camera.image_of(frame.u), camera.image_of(frame.v)], 1),
        np.stack([a0, a1]),
        np.stack([b0, b1]),
        camera.image_of(np.subtract(opposite, corner)),
    )
    return BevelFit(op, image, np.concatenate([at, ctrl2[1], ctrl2[2]]), frame)
