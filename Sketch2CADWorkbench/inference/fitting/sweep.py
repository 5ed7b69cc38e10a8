# SPDX-License-Identifier: LGPL-2.1-or-later
"""Sweep regression: circles from ellipses, offset, profile plane and Bezier (paper, Sec. 4.2)."""

from __future__ import annotations

from dataclasses import dataclass, replace

import cadquery as cq
import cv2
import numpy as np

from ...brep.faces import is_curved, model_scale
from ...brep.protocol import FaceRef, Mode, Sweep, straight_profile
from ...render.camera import OrthoCamera
from ...sketch.curves import silhouette_side
from .common import FitError, fit_bezier, resample
from .primitive import choose_option
from .refine import SweepImage, refine_sweep
from .surface import back_project, check_circle_on_surface, face_frame, face_ref, option_frame

# Inner control points of a fitted profile must lie within this share of d beyond the
# circles' planes, and within this multiple of the larger radius from the axis.
PROFILE_SLACK, PROFILE_MAX_R = 0.1, 2.0
# Moves of a whole circle's ellipse tried at most when fitting the other one to its part
# drawn (`fit_moved_ellipse`): a resolution, at least a quarter pixel over a 256 px view.
MOVES = 2048


@dataclass(frozen=True)
class Ellipse:
    """An image ellipse: centre (px), semi-axes a >= b (px), and major-axis angle (rad)."""

    center: np.ndarray
    a: float
    b: float
    angle: float

    def points(self, n: int = 64) -> np.ndarray:
        t = np.linspace(0, 2 * np.pi, n, endpoint=False)
        ca, sa = np.cos(self.angle), np.sin(self.angle)
        x, y = self.a * np.cos(t), self.b * np.sin(t)
        return self.center + np.stack([x * ca - y * sa, x * sa + y * ca], axis=1)


def fit_ellipse(strokes: list[np.ndarray]) -> Ellipse:
    """Least-squares ellipse through the strokes' samples (OpenCV's fitEllipse)."""
    pts = np.concatenate([resample(s) for s in strokes]).astype(np.float32)
    if len(pts) < 6:
        raise FitError("a circle outline is too short to fit an ellipse")
    (cx, cy), (w, h), ang = cv2.fitEllipse(pts)
    if not np.isfinite([cx, cy, w, h]).all() or min(w, h) <= 0:
        raise FitError("a circle outline does not fit an ellipse")
    a, b, theta = w / 2, h / 2, np.radians(ang)
    if b > a:
        a, b, theta = b, a, theta + np.pi / 2
    return Ellipse(np.array([cx, cy]), float(a), float(b), float(theta))


def fit_moved_ellipse(whole: Ellipse, strokes: list[np.ndarray], step: np.ndarray) -> Ellipse:
    """The ellipse `whole` moved along `step` (the image of the sweep's axis) and scaled,
    that the strokes' samples lie closest to: a sweep's two circles lie square to its axis,
    so in a parallel view one outline is the other moved and scaled, and what is drawn
    of one (a hole's floor circle shows only its far part through the opening, a boss's
    base its near half) fixes it from the one drawn whole.

    Raises:
        FitError: the strokes are too short, or `step` is no direction in the image.
    """
    pts = np.concatenate([resample(s) for s in strokes])
    norm = float(np.linalg.norm(step))
    if len(pts) < 6 or norm < 1e-9:
        raise FitError("a circle outline is too short to fit an ellipse")
    u = step / norm
    ca, sa = np.cos(whole.angle), np.sin(whole.angle)

    # each move's scale is the samples' mean radius in the ellipse's own units (1 on it),
    # its misfit their radial distance (pixels) from the ellipse so scaled
    # the moved centre lies within the strokes' reach of the whole one's, on a grid of a
    # quarter pixel (at most MOVES)
    reach = float(np.max(np.linalg.norm(pts - whole.center, axis=1)))
    t = np.linspace(-reach, reach, int(np.clip(8 * reach, 2, MOVES)))
    rel = pts[None] - (whole.center[None] + t[:, None] * u[None])[:, None]  # (T, K, 2)
    x = (rel[..., 0] * ca + rel[..., 1] * sa) / whole.a
    y = (-rel[..., 0] * sa + rel[..., 1] * ca) / whole.b
    rho = np.maximum(np.hypot(x, y), 1e-9)
    scale = rho.mean(axis=1)
    off = (rho - scale[:, None]) * np.linalg.norm(rel, axis=-1) / rho
    k = int(np.argmin(np.sqrt(np.mean(off**2, axis=1))))
    if scale[k] <= 0:
        raise FitError("a circle outline does not fit an ellipse")
    scale = float(scale[k])
    return Ellipse(whole.center + t[k] * u, whole.a * scale, whole.b * scale, whole.angle)


def _offset_along_axis(
    camera: OrthoCamera, c0: np.ndarray, axis: np.ndarray, target: np.ndarray
) -> float:
    """t >= 0 minimising |project(c0 + t axis) - target| (the line search's exact optimum)."""
    p0 = camera.project(c0[None])[0][0]
    step = camera.image_of(axis)
    if step @ step < 1e-6:
        raise FitError(
            "sweep: the axis points at the viewer, so its length cannot be read; turn the view"
        )
    return float((target - p0) @ step / (step @ step))


def _profile_rh(
    camera: OrthoCamera, stroke: np.ndarray, base: Ellipse, c0: np.ndarray, axis: np.ndarray
) -> np.ndarray | None:
    """The stroke's points as (r, h) in the plane through the axis that faces the view
    (where the generator draws c_p, `sketch.curves.sweep_curves`), on the stroke's side
    of the axis. (The paper's plane through the axis and the stroke's foot lifted onto
    c0's plane tilts toward the view when the foot lies off that plane: on a curved f,
    where a profile starts on the surface below T, it read a radial peg's straight side
    as a bulge.)"""
    pts = resample(stroke)
    if np.linalg.norm(pts[0] - base.center) > np.linalg.norm(pts[-1] - base.center):
        pts = pts[::-1]  # run from the base circle to the far one
    side = silhouette_side(axis, camera.basis()[2])
    p0 = camera.project(c0[None])[0][0]
    if (pts.mean(axis=0) - p0) @ camera.image_of(side) < 0:
        side = -side
    normal = np.cross(axis, side)
    try:
        q = camera.back_project_to_plane(pts, c0, normal)
    except ValueError:
        return None
    rel = q - c0
    return np.stack([rel @ side, rel @ axis], axis=1)


def _sweep(
    face: FaceRef, c0: np.ndarray, r0: float, r1: float, d: float, mid: np.ndarray, mode: Mode
) -> Sweep:
    """The Sweep of these parameters, its profile's inner control points `mid` (2, 2)
    kept off the axis and between the circles' planes: heights past d (or below 0) fold
    its surface of revolution back over the far circle (OCCT: an invalid solid), while
    every height within [0, d] keeps c_p between them."""
    mid = np.array(mid, float)
    mid[:, 0] = np.maximum(mid[:, 0], 0.05 * min(r0, r1))
    mid[:, 1] = np.clip(mid[:, 1], 0.0, d)
    return Sweep(
        face,
        tuple(map(float, c0)),
        float(r0),
        float(r1),
        float(d),
        tuple(tuple(map(float, p)) for p in mid),
        mode,
    )


@dataclass(frozen=True, eq=False)
class SweepFit:
    """A sweep read from its strokes, before the joint refinement of its centre, radii
    and offset against all of them (`refine.py`; the profile keeps its shape): as for a
    prism, a caller that weighs several readings of the strokes refines only those it
    may keep."""

    operation: Sweep  # as fitted, unrefined
    image: SweepImage  # how its curves move in the image with its parameters
    side: np.ndarray  # (3,) the unit vectors of the image's `side` and `other`
    other: np.ndarray
    strokes: list[np.ndarray]  # every stroke of the sweep (circles and profiles)
    curved: bool  # f is curved: the base circle follows the surface

    @property
    def straight(self) -> bool:
        """Whether the profile was fitted straight (no profile stroke bent it)."""
        return not np.any(self.image.bulge)

    def refined(self, straight: bool = False) -> Sweep:
        """The operation with its centre (in f's plane), radii and offset refined together
        against all the strokes, its profile keeping its shape (`refine.SweepImage`), or
        made straight first (`straight`: a cone or cylinder whose radii and offset the
        strokes fix without a bulge the fit drew from the noise of its profile strokes);
        as fitted on a curved f (the refinement draws the base circle flat), made straight
        there without refining."""
        op = self.operation
        if self.curved:
            return replace(op, profile=straight_profile(op.r0, op.r1, op.d)) if straight else op
        image = replace(self.image, bulge=np.zeros((2, 2))) if straight else self.image
        a, b, r0, r1, d = refine_sweep(
            image, np.array([0.0, 0.0, op.r0, op.r1, op.d]), self.strokes
        )
        c0 = np.asarray(op.center, float) + a * self.side + b * self.other
        mid = np.array(straight_profile(r0, r1, d)) + image.bulge
        return _sweep(op.face, c0, r0, r1, d, mid, op.mode)


def fit_sweep(
    solid: cq.Shape,
    face: cq.Face,
    camera: OrthoCamera,
    strokes: list[np.ndarray],
    labels: list[int],
    option: Mode | None = None,
) -> Sweep:
    """Fit a swept solid to circle outlines (start 0 / end 2) and profile strokes (1):
    `sweep_fit`, refined (`SweepFit.refined`). Same arguments and errors."""
    return sweep_fit(solid, face, camera, strokes, labels, option).refined()


def sweep_fit(
    solid: cq.Shape,
    face: cq.Face,
    camera: OrthoCamera,
    strokes: list[np.ndarray],
    labels: list[int],
    option: Mode | None = None,
) -> SweepFit:
    """Fit a swept solid to circle outlines (start 0 / end 2) and profile strokes (1), up
    to the joint refinement.

    Args:
        solid, face, camera: the context solid, base face f and context camera.
        strokes, labels: the strokes (context pixels) and their classes by counting.
        option: force the Boolean (the user's choice); None decides from the strokes.
    Raises:
        FitError: a missing circle outline, neither outline on f, an axis seen end-on,
            or a far circle on the wrong side.

    On a curved f, c0's centre is where the base ellipse's centre meets the surface,
    carried onto the tangent plane there (`surface.py`), and d is measured from it.
    Returns:
        The fit, its Sweep operation unrefined.
    """
    groups = {k: [s for s, l in zip(strokes, labels, strict=True) if l == k] for k in (0, 1, 2)}
    if not groups[0] or not groups[2]:
        raise FitError("a sweep needs both circle outlines (its two ends) to be drawn")
    e_e = fit_ellipse(groups[2])  # the end circle: seen whole on a boss's top, a hole's rim
    e_s = (
        fit_ellipse(groups[0])
        if is_curved(face)  # the base circle follows the surface: no moved copy
        else fit_moved_ellipse(
            e_e, groups[0], camera.image_of(face_frame(face, camera, e_e.points()).normal)
        )
    )
    frame = option_frame(face, camera, e_s.points(), e_e.points())
    scale = model_scale(solid)
    mode = choose_option(face, frame, camera, e_s.points(), e_e.points(), option)
    base, far = (e_s, e_e) if mode is not Mode.SUBTRACT else (e_e, e_s)
    frame = face_frame(face, camera, base.points())
    c0 = back_project(camera, face, frame, base.center[None])[0]
    axis = frame.normal * mode.sign
    d = _offset_along_axis(camera, c0, axis, far.center)
    if d <= 1e-4 * scale:
        raise FitError(
            "sweep: the far circle does not lie beyond the base circle along the face normal"
        )
    r0, r1 = base.a * camera.pixel_size, far.a * camera.pixel_size
    check_circle_on_surface(face, frame, c0, r0)
    inner = []
    for s in groups[1]:
        rh = _profile_rh(camera, s, base, c0, axis)
        if rh is not None and len(rh) >= 4:
            ctrl = fit_bezier(rh, np.array([r0, 0.0]), np.array([r1, d]))
            r, h = ctrl[1:3, 0], ctrl[1:3, 1]
            # a profile that leaves the band between the circles, or swings far out, is
            # a stroke back-projected badly (a short sweep seen obliquely), not a shape
            if np.all(
                (h >= -PROFILE_SLACK * d)
                & (h <= (1 + PROFILE_SLACK) * d)
                & (r > 0)
                & (r <= PROFILE_MAX_R * max(r0, r1))
            ):
                inner.append(ctrl[1:3])
    # no profile drawn: the straight one
    mid = np.mean(inner, axis=0) if inner else np.array(straight_profile(r0, r1, d))
    op = _sweep(face_ref(face, frame), c0, r0, r1, d, mid, mode)
    side = silhouette_side(axis, camera.basis()[2])
    other = np.cross(axis, side)
    image = SweepImage(
        camera.project(c0[None])[0][0],
        camera.image_of(side),
        camera.image_of(other),
        camera.image_of(axis),
        np.array(op.profile) - np.array(straight_profile(r0, r1, d)),
    )
    return SweepFit(op, image, side, other, groups[0] + groups[1] + groups[2], is_curved(face))
