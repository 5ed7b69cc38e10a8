# SPDX-License-Identifier: LGPL-2.1-or-later
"""Back-projecting strokes onto a base face f that may be curved (#16, beyond the paper).

On a planar f a stroke's pixels are back-projected onto f's plane (the paper). On a
cylinder's or cone's side they are back-projected onto the surface itself: each pixel's
view ray is intersected with the surface (`surface_hits`), at the first crossing where
the face looks at the viewer. A prism or sweep on a curved f is given in the tangent
plane T of f at the step's point p_f (brep/protocol): `face_frame` finds p_f under the
base outline and T there, `back_project` carries the base outline's pixels onto the
surface and then along n_f onto T, and `face_ref` names f for the protocol.
"""
from __future__ import annotations

import cadquery as cq
import numpy as np

from ...brep.faces import (
    CurvedSurface,
    FaceFrame,
    face_ref_at,
    face_ref_of,
    is_curved,
    model_scale,
    points_on_face,
)
from ...brep.geometry import plane_basis
from ...brep.protocol import FaceRef
from ...render.camera import OrthoCamera
from .common import FitError


def surface_hits(camera: OrthoCamera, pixels: np.ndarray, face: cq.Face) -> np.ndarray:
    """World points (K, 3) where the view rays of pixels (K, 2) first meet the curved face
    f from the viewer's side (where f's outward normal faces the viewer), NaN rows where
    a ray misses f."""
    surface = CurvedSurface.of(face)
    origins, forward = camera.ray(np.atleast_2d(pixels))
    scale = model_scale(face)
    centre_depth = float((np.array(face.Center().toTuple()) - origins[0]) @ forward)
    k, hit_t, entering = surface.roots(origins, forward, centre_depth - scale,
                                       centre_depth + scale)
    # a convex face looks at the viewer where the ray enters the surface, a concave one
    # (a bore's wall) where it leaves it
    facing = entering == surface.convex
    out = np.full((len(origins), 3), np.nan)
    for i in np.unique(k[facing]):
        for ti in np.sort(hit_t[facing & (k == i)]):
            p = origins[i] + ti * forward
            if points_on_face(face, p[None], 1e-3 * scale)[0]:
                out[i] = p
                break
    return out


def face_frame(face: cq.Face, camera: OrthoCamera, outline: np.ndarray) -> FaceFrame:
    """The plane a step on f is given in: f's own plane if f is planar; on a curved f,
    the tangent plane T at p_f, the surface point under the centre of the base outline
    (pixels (K, 2): a prism's corners, points along a circle): the point of f nearest
    the mean of their back-projections onto f.

    Raises:
        FitError: on a curved f, the outline does not lie on f.
    """
    if not is_curved(face):
        return FaceFrame.of(face)
    hits = surface_hits(camera, outline, face)
    hits = hits[~np.isnan(hits[:, 0])]
    if len(hits) < max(3, len(outline) // 2):
        raise FitError("the base outline does not lie on the curved face it was drawn on")
    at = face_ref_at(face, hits.mean(axis=0))  # the surface's point nearest the mean
    n = np.asarray(at.normal, float)
    return FaceFrame(np.asarray(at.point, float), n, *plane_basis(n))


def back_project(camera: OrthoCamera, face: cq.Face, frame: FaceFrame,
                 pixels: np.ndarray) -> np.ndarray:
    """Base-outline pixels (K, 2) as points (K, 3) of the step's plane (`face_frame`): on
    a planar f where their rays meet it; on a curved f where their rays meet the surface,
    carried along n_f onto the tangent plane T (the base polygon c, or c0's centre).

    Raises:
        FitError: a ray misses the curved f.
    """
    if not is_curved(face):
        return camera.back_project_to_plane(pixels, frame.origin, frame.normal)
    hits = surface_hits(camera, pixels, face)
    if np.isnan(hits).any():
        raise FitError("a corner of the base outline does not lie on the curved face")
    return hits - np.outer((hits - frame.origin) @ frame.normal, frame.normal)


def face_ref(face: cq.Face, frame: FaceFrame) -> FaceRef:
    """f for the protocol: a planar face as `face_ref_of` names it; a curved one by p_f,
    n_f there and its surface's kind."""
    if not is_curved(face):
        return face_ref_of(face)
    return FaceRef(tuple(float(c) for c in frame.origin), tuple(float(c) for c in frame.normal),
                   CurvedSurface.of(face).kind)
