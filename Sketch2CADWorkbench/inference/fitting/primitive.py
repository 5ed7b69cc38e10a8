# SPDX-License-Identifier: LGPL-2.1-or-later
"""What add/subtract prisms and sweeps share: the base face's outline and the +/- option."""

from __future__ import annotations

import cadquery as cq
import numpy as np
from matplotlib.path import Path as MplPath

from ...brep.faces import FaceFrame, points_on_face
from ...brep.protocol import AddSubPrism, Mode, Sweep
from ...render.camera import OrthoCamera
from .common import FitError

# Fraction of a back-projected outline's samples on f for it to lie on f; below it, an
# outline that is mostly on f still decides when the other one is less so
# (docs/measurements.md, primitive.MOSTLY_FRACTION).
ON_FACE_FRACTION = 0.9
MOSTLY_FRACTION = 0.25
# Share of f an outline's region must cover to stand on f when its outline does not lie
# on f at all (a plate wider than the column top it stands on).
COVER_FRACTION = 0.5
# An outline sample back-projected within this many context pixels of f counts as on f:
# the hand's slack where a boss stands at f's edge (a fitted base outline 1-2 px over the
# edge read the boss as the hole its top draws): docs/measurements.md,
# primitive.ON_FACE_TOL_PX.
ON_FACE_TOL_PX = 2.0


def on_face_tolerance(camera: OrthoCamera) -> float:
    """ON_FACE_TOL_PX in mm on f's plane, for `points_on_face`."""
    return ON_FACE_TOL_PX * camera.pixel_size


def fraction_on_face(face: cq.Face, pts3d: np.ndarray, tol: float) -> float:
    """The fraction of the points (on f's plane) that lie inside f."""
    return float(np.mean(points_on_face(face, pts3d, tol)))


def covered_share(
    face: cq.Face,
    frame: FaceFrame,
    camera: OrthoCamera,
    outline: np.ndarray,
    tol: float,
    grid: int = 16,
) -> float:
    """The share of f's area inside an outline (K, 2 pixels) back-projected onto f's plane:
    how much of f a primitive with that base outline would stand on."""
    # f's box, not its vertices: a disc (a post's top) has one vertex
    b = face.BoundingBox()
    bb = frame.to_2d(
        np.array(
            [
                (x, y, z)
                for x in (b.xmin, b.xmax)
                for y in (b.ymin, b.ymax)
                for z in (b.zmin, b.zmax)
            ]
        )
    )
    lo, hi = bb.min(axis=0), bb.max(axis=0)
    u, v = np.meshgrid(np.linspace(lo[0], hi[0], grid), np.linspace(lo[1], hi[1], grid))
    pts = frame.to_3d(np.stack([u.ravel(), v.ravel()], axis=1))
    on_f = pts[points_on_face(face, pts, tol)]
    if not len(on_f):
        return 0.0
    return float(np.mean(MplPath(outline).contains_points(camera.project(on_f)[0])))


def _outline_share(
    face: cq.Face, frame: FaceFrame, camera: OrthoCamera, outline: np.ndarray, tol: float
) -> float:
    """The share of the outline's samples and centre that back-project onto f."""
    return fraction_on_face(
        face,
        camera.back_project_to_plane(
            np.concatenate([outline, outline.mean(axis=0)[None]]), frame.origin, frame.normal
        ),
        tol,
    )


def stands_on_face(
    face: cq.Face, frame: FaceFrame, camera: OrthoCamera, outline: np.ndarray, tol: float
) -> bool:
    """Whether a primitive with this base outline (K, 2 pixels) could stand on f: a
    quarter of the outline back-projects onto f, or its region covers half of f."""
    return (
        _outline_share(face, frame, camera, outline, tol) >= MOSTLY_FRACTION
        or covered_share(face, frame, camera, outline, tol) >= COVER_FRACTION
    )


def choose_option(
    face: cq.Face,
    frame: FaceFrame,
    camera: OrthoCamera,
    start_2d: np.ndarray,
    end_2d: np.ndarray,
    forced: Mode | None,
) -> Mode:
    """The +/- option: + when the start outline lies on f, else - when the end one does.

    Start and end are ordered along n_f, so for an addition the start outline is on f
    and for a subtraction the end outline is. When both could be (the ambiguous case of
    the paper's Fig. 5b), + is the default. An outline "lies on f" when 90% of its
    back-projected samples (and its centre) do; failing that for both (a plate wider
    than the column top it stands on), the outline whose region covers more of f, if
    that covers at least half of it; failing that too (a primitive overhanging f's
    edge), the one more on f if a quarter of it is. Covering comes first: a plate's far
    outline, back-projected past its rim, can land a quarter on f while the plate's own
    base covers all of f (examples/sessions/hammer.json, step 5). A sample within
    ON_FACE_TOL_PX of f is on it. `forced` (the user's choice) wins, when its base
    outline meets f by one of these tests.

    Args:
        start_2d, end_2d: points along the two closed outlines (K, 2 context pixels).
    Raises:
        FitError: neither outline (or not the forced option's) meets the base face.
    """
    outlines, tol = (start_2d, end_2d), on_face_tolerance(camera)
    if forced is not None:
        if stands_on_face(face, frame, camera, outlines[forced is Mode.SUBTRACT], tol):
            return forced
        raise FitError(
            f"the {forced.value} option needs its base outline on the base face, "
            "and it is not there"
        )
    on = [_outline_share(face, frame, camera, o, tol) for o in outlines]
    if on[0] >= ON_FACE_FRACTION:
        return Mode.ADD
    if on[1] >= ON_FACE_FRACTION:
        return Mode.SUBTRACT
    covered = [covered_share(face, frame, camera, o, tol) for o in outlines]
    if max(covered) >= COVER_FRACTION:
        return Mode.ADD if covered[0] >= covered[1] else Mode.SUBTRACT
    if max(on) >= MOSTLY_FRACTION:
        return Mode.ADD if on[0] >= on[1] else Mode.SUBTRACT
    raise FitError(
        "neither the start nor the end outline meets the base face, so the "
        "sketch matches no addition or subtraction"
    )


def base_centre(op: AddSubPrism | Sweep) -> np.ndarray:
    """Where a primitive stands on f (mm, (3,)): its base polygon's centre, or its base
    circle's centre c0 (both lie on f's plane for either Boolean)."""
    if isinstance(op, Sweep):
        return np.asarray(op.center, float)
    return np.asarray(op.polygon, float).mean(axis=0)


def far_outline(op: AddSubPrism | Sweep, frame: FaceFrame) -> np.ndarray:
    """Points (K, 3) along the primitive's outline away from f (its far end), in mm."""
    shift = frame.normal * op.d * op.mode.sign
    if isinstance(op, AddSubPrism):
        poly = np.array(op.polygon, float)
        closed = np.concatenate([poly, poly[:1]])
        edges = [
            np.linspace(closed[i], closed[i + 1], 16, endpoint=False) for i in range(len(poly))
        ]
        return np.concatenate(edges) + shift
    t = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    centre = frame.to_2d(np.array(op.center, float))[0]
    ring = centre + op.r1 * np.stack([np.cos(t), np.sin(t)], axis=1)
    return frame.to_3d(ring) + shift


def base_share(face: cq.Face, camera: OrthoCamera, op: AddSubPrism | Sweep) -> float:
    """The share of the primitive's base outline (on f's plane) that lies on f: where it
    would stand relative to f's outline."""
    frame = FaceFrame.of(face)
    base = far_outline(op, frame) - frame.normal * op.d * op.mode.sign
    return fraction_on_face(face, base, on_face_tolerance(camera))


def far_outline_share(face: cq.Face, camera: OrthoCamera, op: AddSubPrism | Sweep) -> float:
    """The share of the primitive's far outline (and its centre) that, back-projected
    along the view onto f's plane, lies on f."""
    frame = FaceFrame.of(face)
    return _outline_share(
        face, frame, camera, camera.project(far_outline(op, frame))[0], on_face_tolerance(camera)
    )


def other_option_fits(face: cq.Face, camera: OrthoCamera, op: AddSubPrism | Sweep) -> bool:
    """Whether the flipped Boolean explains the same strokes (the paper's Fig. 5b).

    In a parallel view, a boss on f and a hole into f whose rim is the boss's top
    outline, seen along the view, draw the same lines. The flipped reading stands on the
    fitted primitive's far outline, back-projected along the view onto f; it is named
    when that outline stands on f by the test a forced Boolean must pass
    (`stands_on_face`), so that choosing it reads it. A stricter test than the forced
    one (half the outline on f) would name no flip for a boss overhanging f's edge, read
    as the hole its top draws.
    """
    if op.mode not in (Mode.ADD, Mode.SUBTRACT):
        return False
    frame = FaceFrame.of(face)
    return stands_on_face(
        face, frame, camera, camera.project(far_outline(op, frame))[0], on_face_tolerance(camera)
    )
