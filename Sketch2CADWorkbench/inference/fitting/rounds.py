# SPDX-License-Identifier: LGPL-2.1-or-later
"""A bevel's profile drawn across an edge: the edge it crosses and l fitted across it.

The profile stroke of a round or chamfer runs from one face over an edge onto the face
beyond: across a straight edge, or across a circular rim where a planar face meets a
cylinder or cone (the top of a knob, the mouth of a hole). `round_fits` finds the edges
whose image the stroke crosses or passes nearest (straight edges and circular rims
between a planar face f and another face), takes c where the stroke is nearest the
edge's image, back-projects the stroke onto the plane normal to the edge at c, and fits
l there as a cubic Bezier from f's trace (l(0)) to the other face's (l(1)), each a
straight line from c in that plane (a plane's, or a cylinder's or cone's generatrix).
Along a tangent chain or a face's outline, which OCCT follows only with a fillet or a
chamfer, l is read as the nearer of the two (regularize.nearest_regular).
"""

from __future__ import annotations

import cadquery as cq
import numpy as np

from ...brep.faces import FaceFrame, face_ref_of, model_scale
from ...brep.geometry import vec3
from ...brep.protocol import Bevel, EdgeSet
from ...brep.rounds import (
    edge_faces,
    faces_of,
    far_copy,
    into_face,
    point_on_edge,
    traces,
)
from ...render.camera import OrthoCamera
from .bevel import EDGE_TOL, INNER_SPAN
from .common import FitError, fit_bezier, resample
from .regularize import nearest_regular

# Edges tried per profile stroke, the nearest (in the image) first
# (docs/measurements.md, rounds.EDGES_TRIED).
EDGES_TRIED = 3
# Points an edge is sampled at to find where the stroke crosses its image; first
# COARSE_SAMPLES, to pass over an edge whose image lies far from the stroke.
EDGE_SAMPLES = 256
COARSE_SAMPLES = 17
# The plane l is drawn in must face the view: the cosine between the edge's tangent (the
# plane's normal) and the view direction is at least this, or the stroke back-projects
# onto it ill-conditioned (a rim's profile is drawn where the rim turns across the view;
# docs/measurements.md, rounds.FACING_COS).
FACING_COS = 0.3


def round_fits(
    solid: cq.Shape,
    camera: OrthoCamera,
    stroke: np.ndarray,
    edges: EdgeSet = EdgeSet.DRAWN,
    others: list[np.ndarray] | None = None,
) -> list[Bevel]:
    """Bevels across an edge that the profile stroke may draw, the edge it fits best (in
    the image) first, each with the edge set `edges` (module docstring); `others`, the
    sketch's other strokes, may hold l' drawn again (`_fit_across`).

    Raises:
        FitError: no straight edge or circular rim between a planar face and another
            face has its traces within EDGE_TOL of the stroke's ends where its plane
            faces the view.
    """
    stroke = resample(np.asarray(stroke, float).reshape(-1, 2))
    tol = EDGE_TOL * float(np.hypot(camera.width, camera.height))
    faces_map = edge_faces(solid)
    near = []
    for edge in solid.Edges():
        if edge.geomType() not in ("LINE", "CIRCLE"):
            continue
        faces = faces_of(faces_map, edge)
        if len(faces) != 2 or not any(f.geomType() == "PLANE" for f in faces):
            continue
        found = _crossing(edge, faces, camera, stroke, tol)
        if found is not None and found[0] <= tol:
            near.append((found, edge, faces))
    near.sort(key=lambda n: n[0][0])
    out = []
    for (_, c, flip), edge, faces in near[:EDGES_TRIED]:
        drawn = stroke[::-1] if flip else stroke
        op = _fit_across(solid, camera, drawn, edge, c, faces, edges, others or [])
        if op is not None:
            out.append(op)
    if not out:
        raise FitError(
            "bevel: the profile stroke runs across no straight edge or circular rim between "
            "a planar face and another face, seen from where its profile faces the view"
        )
    return out


def _crossing(
    edge: cq.Edge, faces: list[cq.Face], camera: OrthoCamera, stroke: np.ndarray, tol: float
) -> tuple[float, np.ndarray, bool] | None:
    """Where along the edge the stroke is drawn across it: the point c whose two traces
    (`brep.rounds.traces`, seen in the image) pass nearest the stroke's two ends, the planar face's
    at the stroke's start (else the stroke is `flip`ped), among EDGE_SAMPLES points where
    the plane normal to the edge faces the view (FACING_COS). Returns (the two ends'
    distances from their traces, px; c; flip), or None where the edge's image lies
    farther than `tol` (px) from the stroke or no point faces the view."""
    # a coarse look first: most edges of a model lie far from the stroke, and OCCT's
    # evaluations of EDGE_SAMPLES points on each cost most of a bevel's reading
    coarse = camera.project(
        [edge.positionAt(t).toTuple() for t in np.linspace(0, 1, COARSE_SAMPLES)]
    )[0]
    spacing = float(np.linalg.norm(np.diff(coarse, axis=0), axis=1).max())
    if np.linalg.norm(coarse[:, None] - stroke[None], axis=2).min() > tol + spacing:
        return None  # no point between two samples lies nearer than that
    params = np.linspace(0, 1, EDGE_SAMPLES, endpoint=not edge.IsClosed())
    if edge.geomType() == "LINE":  # exact, without OCCT's per-point evaluations
        a, b = (np.array(v.toTuple()) for v in (edge.startPoint(), edge.endPoint()))
        c = a + params[:, None] * (b - a)
        t = np.repeat((b - a)[None], len(params), axis=0)
    else:
        c = np.array([edge.positionAt(t).toTuple() for t in params])
        t = np.array([edge.tangentAt(p).toTuple() for p in params])
    image = camera.project(c)[0]
    if np.linalg.norm(image[:, None] - stroke[None], axis=2).min() > tol:
        return None
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    facing = np.abs(t @ np.asarray(camera.direction, float)) >= FACING_COS
    if not facing.any():
        return None
    k = next(i for i, face in enumerate(faces) if face.geomType() == "PLANE")
    lines = [_image_dirs(camera, traces(face, c, t)) for face in (faces[k], faces[1 - k])]
    ends = stroke[[0, -1]]
    best = None
    for flip, (start, end) in ((False, ends), (True, ends[::-1])):
        gap = _off_lines(start, image, lines[0]) + _off_lines(end, image, lines[1])
        gap = np.where(facing, gap, np.inf)
        i = int(np.argmin(gap))
        if best is None or gap[i] < best[0]:
            best = (float(gap[i]), c[i], flip)
    return best


def _image_dirs(camera: OrthoCamera, u: np.ndarray) -> np.ndarray:
    """Unit image directions (K, 2) of world directions (K, 3)."""
    centre = np.asarray(camera.center, float)
    w = camera.project(centre + np.asarray(u, float))[0] - camera.project(centre)[0]
    return w / np.maximum(np.linalg.norm(w, axis=1, keepdims=True), 1e-12)


def _off_lines(p: np.ndarray, origins: np.ndarray, dirs: np.ndarray) -> np.ndarray:
    """The distances (px, (K,)) of p from the lines through origins (K, 2) along the unit
    directions dirs (K, 2)."""
    d = p - origins
    return np.abs(d[:, 0] * dirs[:, 1] - d[:, 1] * dirs[:, 0])


def _fit_across(
    solid: cq.Shape,
    camera: OrthoCamera,
    stroke: np.ndarray,
    edge: cq.Edge,
    c: np.ndarray,
    faces: list[cq.Face],
    edges: EdgeSet,
    others: list[np.ndarray],
) -> Bevel | None:
    """l fitted across `edge` at c from its planar face f (the stroke's start) to the
    other (None: the edge has no face on a side, or the plane is seen edge-on).

    The stroke is back-projected onto l's plane; so is the other stroke that draws l'
    where the sketch has it (brep/rounds.far_copy), carried back onto l's plane, when
    one lies within l's size of l: l's ends are where the strokes' ends lie along the
    faces' traces, its inner control points fitted to each, on average, as the hand's
    error of two strokes averages out."""
    c, t = point_on_edge(edge, c)
    k = next(i for i, face in enumerate(faces) if face.geomType() == "PLANE")
    f, g = faces[k], faces[1 - k]
    scale = model_scale(solid)
    try:
        drawn = [camera.back_project_to_plane(stroke, c, t)]
    except ValueError:
        return None
    u_f, u_g = (into_face(face, c, t, 1e-3 * scale) for face in (f, g))
    if u_f is None or u_g is None:
        return None
    second = _second_stroke(edge, c, t, camera, others, drawn[0], u_f)
    if second is not None:
        drawn.append(second)
    reach_f, reach_g = (
        max(float(np.mean([(p[i] - c) @ u for p in drawn])), 1e-3 * scale)
        for i, u in ((0, u_f), (-1, u_g))
    )
    frame = FaceFrame(c, t, u_f, np.cross(t, u_f))
    a, b = frame.to_2d(c + reach_f * u_f)[0], frame.to_2d(c + reach_g * u_g)[0]
    fits = [fit_bezier(frame.to_2d(p), a, b, corner=np.zeros(2), span=INNER_SPAN) for p in drawn]
    p0, p1, p2, p3 = (vec3(p) for p in frame.to_3d(np.mean(fits, axis=0)))
    op = Bevel(face_ref_of(f), vec3(c), None, (p0, p1, p2, p3), edges)
    # OCCT follows a chain or an outline only with a fillet or a chamfer
    return op if edges is EdgeSet.DRAWN else nearest_regular(op)


def _second_stroke(
    edge: cq.Edge,
    c: np.ndarray,
    t: np.ndarray,
    camera: OrthoCamera,
    others: list[np.ndarray],
    first: np.ndarray,
    u_f: np.ndarray,
) -> np.ndarray | None:
    """Of the other strokes, the one that draws l' (brep/rounds.far_copy) nearest the
    first stroke's l, back-projected onto l''s plane and carried onto l's, its start on
    f's side; None when none lies within l's size of it."""
    size = float(np.linalg.norm(first[-1] - first[0]))
    far_c = far_copy(edge, c, c[None])[0]
    best = None
    for other in others:
        try:
            pts = far_copy(edge, c, camera.back_project_to_plane(other, far_c, t), back=True)
        except ValueError:
            continue
        if float((pts[0] - c) @ u_f) < float((pts[-1] - c) @ u_f):
            pts = pts[::-1]
        gap = float(np.linalg.norm(pts[:, None] - first[None], axis=2).min(axis=1).mean())
        if gap <= size and (best is None or gap < best[0]):
            best = (gap, pts)
    return None if best is None else best[1]
