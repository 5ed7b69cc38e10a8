# SPDX-License-Identifier: LGPL-2.1-or-later
"""Bevel regression: profile l, corner c and opposite corner c' (paper, "Bevel regression")."""
from __future__ import annotations

import cadquery as cq
import numpy as np

from ...brep.corners import crease_end, line_edges
from ...brep.faces import FaceFrame, face_ref_of, model_scale
from ...brep.protocol import Bevel
from ...render.camera import OrthoCamera
from .common import FitError, fit_bezier, resample

# How far (relative to the model diagonal) a profile end may lie from an edge of f.
EDGE_TOL = 0.08


def _corner_for(pts: np.ndarray, edges, scale: float
                ) -> tuple[np.ndarray, tuple[np.ndarray, np.ndarray]]:
    """The corner c of f whose two edges best hold the stroke's two ends.

    For every vertex shared by two straight edges of f, each stroke end is put on the
    nearer of the two edges (the other end on the other edge); the corner with the
    smallest total distance wins. Returns c and the ends snapped onto the edges.
    """
    best = None
    for i, (a0, a1) in enumerate(edges):
        for j, (b0, b1) in enumerate(edges[i + 1:], i + 1):
            for p in (a0, a1):
                for q in (b0, b1):
                    if np.linalg.norm(p - q) > 1e-6 * scale:
                        continue
                    ea, eb = (a0, a1), (b0, b1)
                    for first, second in ((ea, eb), (eb, ea)):
                        qa, da = _on_segment(pts[0], *first)
                        qb, db = _on_segment(pts[-1], *second)
                        if best is None or da + db < best[0]:
                            best = (da + db, p, (qa, qb))
    if best is None:
        raise FitError("bevel: the face has no corner between two straight edges")
    if best[0] > 2 * EDGE_TOL * scale:
        raise FitError("bevel: the profile stroke must run from one edge of the face to another")
    return best[1], best[2]


def _on_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, float]:
    """The point of segment a-b nearest to p (kept off the ends), and the distance."""
    ab = b - a
    t = float(np.clip((p - a) @ ab / (ab @ ab), 0.02, 0.98))
    q = a + t * ab
    return q, float(np.linalg.norm(p - q))


def _inside_wedge(ctrl: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Move inner control points onto the corner's side of both edges (2D, face frame).

    A noisy stroke can make l bulge past an edge of f; with all control points inside
    the wedge at c, the whole curve is (convex hull property) and the bevel is valid.
    """
    out = ctrl.copy()
    a, b = ctrl[0] - c, ctrl[3] - c
    s = np.sign(a[0] * b[1] - a[1] * b[0])
    for i in (1, 2):
        for edge, sign in ((a, s), (b, -s)):
            q = out[i] - c
            if sign * (edge[0] * q[1] - edge[1] * q[0]) < 0:  # beyond this edge's line
                out[i] = c + edge * (q @ edge) / (edge @ edge)
    return out


def fit_bevel(solid: cq.Shape, face: cq.Face, camera: OrthoCamera,
              profile_stroke: np.ndarray) -> Bevel:
    """Fit l as a cubic Bezier to the profile stroke back-projected onto f's plane.

    Args:
        solid: the context solid.
        face: the base face f.
        camera: the context camera; the stroke is in its pixels.
        profile_stroke: the stroke s* with the most l votes (C > 0.5), (K, 2).
    Raises:
        FitError: the stroke's ends do not land on two edges of f that meet at a
            corner, or that corner has no crease along -n_f.
    Returns:
        The Bevel on f with corner c where l's two edges meet.
    """
    frame = FaceFrame.of(face)
    scale = model_scale(solid)
    try:
        pts = camera.back_project_to_plane(resample(profile_stroke), frame.origin, frame.normal)
    except ValueError as e:
        raise FitError(f"bevel: {e}") from None
    corner, (qa, qb) = _corner_for(pts, line_edges(face), scale)
    opposite = crease_end(solid, corner, frame.normal, 1e-6 * scale)
    if opposite is None:
        raise FitError("bevel: the corner has no edge running into the solid along the face "
                       "normal, so there is no crease to round")
    ctrl2 = fit_bezier(frame.to_2d(pts), frame.to_2d(qa)[0], frame.to_2d(qb)[0])
    ctrl = frame.to_3d(_inside_wedge(ctrl2, frame.to_2d(corner)[0]))
    return Bevel(face_ref_of(face), tuple(map(float, corner)), tuple(map(float, opposite)),
                 tuple(tuple(map(float, p)) for p in ctrl))
