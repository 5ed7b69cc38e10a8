# SPDX-License-Identifier: LGPL-2.1-or-later
"""Back-projecting strokes onto a base face f that may be curved (beyond the paper).

On a planar f a stroke's pixels are back-projected onto f's plane (the paper). On a
cylinder's or cone's side they are back-projected onto the surface itself: each pixel's
view ray is intersected with the surface (`surface_hits`), at the first crossing where
the face looks at the viewer, or within the hand's slack past its outline or rims. A
prism or sweep on a curved f is given in the tangent plane T of f at the step's point
p_f (brep/protocol): `option_frame` finds the T its +/- option is read in, under the
outline on f, `face_frame` finds p_f under the base outline and T there, `back_project`
carries the base outline's pixels onto the surface and then along n_f onto T, and
`face_ref` names f for the protocol.
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

# A ray that misses the curved f by at most this many pixels still meets it (a corner
# drawn past a cylinder's outline or rim by the hand; level-1 profile strokes end several
# pixels from the true corners): docs/measurements.md, surface.SURFACE_SLACK_PX.
SURFACE_SLACK_PX = 6.0


def surface_hits(camera: OrthoCamera, pixels: np.ndarray, face: cq.Face) -> np.ndarray:
    """World points (K, 3) where the view rays of pixels (K, 2) first meet the curved face
    f from the viewer's side (where f's outward normal faces the viewer), NaN rows where
    a ray misses f by more than the hand's slack, SURFACE_SLACK_PX: a ray that meets the
    surface that close past f's rim takes that point, and one that passes that close
    outside a convex surface (a corner drawn just past a post's outline) the surface
    point nearest its closest approach to the axis."""
    surface = CurvedSurface.of(face)
    origins, forward = camera.ray(np.atleast_2d(pixels))
    scale = model_scale(face)
    slack = max(1e-3 * scale, SURFACE_SLACK_PX * camera.pixel_size)
    centre_depth = float((np.array(face.Center().toTuple()) - origins[0]) @ forward)
    k, hit_t, entering = surface.roots(origins, forward, centre_depth - scale, centre_depth + scale)
    # a convex face looks at the viewer where the ray enters the surface, a concave one
    # (a bore's wall) where it leaves it
    facing = entering == surface.convex
    out = np.full((len(origins), 3), np.nan)
    for i in np.unique(k[facing]):
        for ti in np.sort(hit_t[facing & (k == i)]):
            p = origins[i] + ti * forward
            if points_on_face(face, p[None], slack)[0]:
                out[i] = p
                break
    missed = np.flatnonzero(~np.isin(np.arange(len(origins)), k))  # never met the surface
    if len(missed) and surface.convex:  # (a bore's wall is not seen from outside it)
        near, apart = _grazing(surface, origins[missed], forward)
        ok = (apart <= slack) & points_on_face(face, near, slack)
        out[missed[ok]] = near[ok]
    return out


def _grazing(
    surface: CurvedSurface, origins: np.ndarray, forward: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """For rays (origins (K, 3), one direction) that miss the surface, so pass outside
    it: the surface point at the height and on the side of each ray's closest approach
    to the axis (the point of the surface's outline it passes nearest: exactly on a
    cylinder, nearly on a cone) (K, 3), and how far outside the surface the ray passes
    there (K,) (inf for a ray along the axis)."""
    a = surface.axis
    across = (origins - surface.origin) - np.outer((origins - surface.origin) @ a, a)
    step = forward - (forward @ a) * a
    if step @ step < 1e-12:
        return np.array(origins, float), np.full(len(origins), np.inf)
    closest = origins + np.outer(-(across @ step) / (step @ step), forward)
    rel = closest - surface.origin
    h = rel @ a
    radial = rel - np.outer(h, a)
    radial /= np.linalg.norm(radial, axis=1, keepdims=True)
    on = surface.origin + np.outer(h, a) + surface.radius_at(closest)[:, None] * radial
    return on, surface.level(closest)


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
    return _frame_under(face, surface_hits(camera, outline, face))


def _frame_under(face: cq.Face, hits: np.ndarray) -> FaceFrame:
    """T at the point of the curved f nearest the mean of an outline's hits (K, 3; NaN
    rows: its rays that miss f), `face_frame`'s.

    Raises:
        FitError: fewer than half the outline's rays (or 3) meet f.
    """
    met = hits[~np.isnan(hits[:, 0])]
    if len(met) < max(3, len(hits) // 2):
        raise FitError("the base outline does not lie on the curved face it was drawn on")
    at = face_ref_at(face, met.mean(axis=0))  # the face's point nearest the mean
    n = np.asarray(at.normal, float)
    return FaceFrame(np.asarray(at.point, float), n, *plane_basis(n))


def option_frame(
    face: cq.Face, camera: OrthoCamera, start: np.ndarray, end: np.ndarray
) -> FaceFrame:
    """The plane the +/- option is read in (`primitive.choose_option`): f's own plane if
    f is planar; on a curved f, T under whichever of the start and end outlines (pixels
    (K, 2)) lies on f the more, the base one. The other stands off f, in the air or at a
    hole's bottom, so it misses f or hits it elsewhere: T under both outlines together
    lay off the base, and half their points missing f refused a boss.

    Raises:
        FitError: neither outline lies on f.
    """
    if not is_curved(face):
        return FaceFrame.of(face)
    hits = [surface_hits(camera, o, face) for o in (start, end)]
    on = [np.mean(~np.isnan(h[:, 0])) for h in hits]
    return _frame_under(face, hits[1] if on[1] > on[0] else hits[0])


def back_project(
    camera: OrthoCamera, face: cq.Face, frame: FaceFrame, pixels: np.ndarray
) -> np.ndarray:
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


def check_circle_on_surface(
    face: cq.Face, frame: FaceFrame, centre: np.ndarray, radius: float
) -> None:
    """On a curved f, refuse a circle of T (a sweep's c0: centre (3,), radius mm) that
    reaches past the surface's side, where the lines along n_f from it miss f (the
    generator cannot draw it, nor the operator build it).

    Raises:
        FitError: the circle is wider than the curved face there.
    """
    if not is_curved(face):
        return
    t = np.linspace(0, 2 * np.pi, 32, endpoint=False)
    ring = centre + radius * (np.outer(np.cos(t), frame.u) + np.outer(np.sin(t), frame.v))
    if np.isnan(CurvedSurface.of(face).crossings(ring, frame.normal, model_scale(face))).any():
        raise FitError("the base circle reaches past the side of the curved face it stands on")


def face_ref(face: cq.Face, frame: FaceFrame) -> FaceRef:
    """f for the protocol: a planar face as `face_ref_of` names it; a curved one by p_f,
    n_f there and its surface's kind."""
    if not is_curved(face):
        return face_ref_of(face)
    return FaceRef(
        tuple(float(c) for c in frame.origin),
        tuple(float(c) for c in frame.normal),
        CurvedSurface.of(face).kind,
    )
