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
"""

from __future__ import annotations

import cadquery as cq
import numpy as np

from ...brep.faces import CurvedSurface, FaceFrame, face_ref_of, model_scale
from ...brep.geometry import vec3
from ...brep.protocol import Bevel, EdgeSet
from ...brep.rounds import edge_faces, faces_of, point_on_edge
from ...render.camera import OrthoCamera
from .bevel import EDGE_TOL, INNER_SPAN
from .common import FitError, fit_bezier, resample

# Edges tried per profile stroke, the nearest (in the image) first.
EDGES_TRIED = 3
# Points an edge is sampled at to find where the stroke crosses its image.
EDGE_SAMPLES = 256
# The plane l is drawn in must face the view: the cosine between the edge's tangent (the
# plane's normal) and the view direction is at least this, or the stroke back-projects
# onto it ill-conditioned (a rim's profile is drawn where the rim turns across the view).
FACING_COS = 0.3


def round_fits(
    solid: cq.Shape, camera: OrthoCamera, stroke: np.ndarray, edges: EdgeSet = EdgeSet.DRAWN
) -> list[Bevel]:
    """Bevels across an edge that the profile stroke may draw, the edge it fits best (in
    the image) first, each with the edge set `edges` (module docstring).

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
        op = _fit_across(solid, camera, stroke[::-1] if flip else stroke, edge, c, faces, edges)
        if op is not None:
            out.append(op)
    if not out:
        raise FitError(
            "bevel: the profile stroke runs across no straight edge or circular rim between "
            "a planar face and another face, seen from where its profile faces the view"
        )
    return out


def _traces(face: cq.Face, c: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The lines (unit directions, either way; (K, 3)) of `face` across the edge at the
    points c (K, 3) where its tangents are t (K, 3), in the plane normal to the edge:
    perpendicular to the edge in the face's tangent plane."""
    if face.geomType() == "PLANE":
        n = np.broadcast_to(np.array(face.normalAt().toTuple()), c.shape)
    else:
        n = CurvedSurface.of(face).normals(c)
    u = np.cross(t, n)
    return u / np.linalg.norm(u, axis=-1, keepdims=True)


def _crossing(
    edge: cq.Edge, faces: list[cq.Face], camera: OrthoCamera, stroke: np.ndarray, tol: float
) -> tuple[float, np.ndarray, bool] | None:
    """Where along the edge the stroke is drawn across it: the point c whose two traces
    (`_traces`, seen in the image) pass nearest the stroke's two ends, the planar face's
    at the stroke's start (else the stroke is `flip`ped), among EDGE_SAMPLES points where
    the plane normal to the edge faces the view (FACING_COS). Returns (the two ends'
    distances from their traces, px; c; flip), or None where the edge's image lies
    farther than `tol` (px) from the stroke or no point faces the view."""
    params = np.linspace(0, 1, EDGE_SAMPLES, endpoint=not edge.IsClosed())
    c = np.array([edge.positionAt(t).toTuple() for t in params])
    image = camera.project(c)[0]
    if np.linalg.norm(image[:, None] - stroke[None], axis=2).min() > tol:
        return None
    t = np.array([edge.tangentAt(p).toTuple() for p in params])
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    facing = np.abs(t @ np.asarray(camera.direction, float)) >= FACING_COS
    if not facing.any():
        return None
    k = next(i for i, face in enumerate(faces) if face.geomType() == "PLANE")
    lines = [_image_dirs(camera, _traces(face, c, t)) for face in (faces[k], faces[1 - k])]
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
    w = np.array([camera.image_of(d) for d in u])
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
) -> Bevel | None:
    """l fitted across `edge` at c from its planar face f (the stroke's start) to the
    other: its ends where the stroke's ends lie along the two traces in the image, its
    inner control points fitted to the stroke back-projected onto l's plane (None: the
    stroke's ends lie off the faces, or the plane is seen edge-on)."""
    c, t = point_on_edge(edge, c)
    k = next(i for i, face in enumerate(faces) if face.geomType() == "PLANE")
    f, g = faces[k], faces[1 - k]
    origin = camera.project(c[None])[0][0]
    scale = model_scale(solid)
    ends = []
    for face, p in ((f, stroke[0]), (g, stroke[-1])):
        u = _traces(face, c[None], t[None])[0]
        w = camera.image_of(u)
        reach = float((p - origin) @ w) / max(float(w @ w), 1e-12)  # mm along u
        u = u if reach >= 0 else -u
        if face.distance(cq.Vertex.makeVertex(*(c + 1e-3 * scale * u))) > 1e-5 * scale:
            return None  # that way from c is not on the face
        ends.append((u, max(abs(reach), 1e-3 * scale)))
    try:
        pts = camera.back_project_to_plane(stroke, c, t)
    except ValueError:
        return None
    (u_f, reach_f), (u_g, reach_g) = ends
    frame = FaceFrame(c, t, u_f, np.cross(t, u_f))
    ctrl2 = fit_bezier(
        frame.to_2d(pts),
        frame.to_2d(c + reach_f * u_f)[0],
        frame.to_2d(c + reach_g * u_g)[0],
        corner=np.zeros(2),
        span=INNER_SPAN,
    )
    p0, p1, p2, p3 = (vec3(p) for p in frame.to_3d(ctrl2))
    return Bevel(face_ref_of(f), vec3(c), None, (p0, p1, p2, p3), edges)
