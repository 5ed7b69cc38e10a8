# SPDX-License-Identifier: LGPL-2.1-or-later
"""Shared pieces of parameter fitting: stroke sampling and counting, line search, Beziers.

All 2D quantities are in the context camera's pixels (render/camera.py convention);
3D quantities are world millimetres.
"""

from __future__ import annotations

import cadquery as cq
import cv2
import numpy as np
from scipy.optimize import linear_sum_assignment

from ...brep.geometry import arc_lengths, bezier, polyline_length, resample_every, resample_polyline
from ...render.camera import OrthoCamera

# A stroke longer than this many times its extent is a loop (a circle drawn once around:
# about pi; a line or a profile curve: 1 to 1.3). Its ends' gap does not tell: the
# level-3 hand leaves a circle's ends apart by 30-50% of its extent, and such a gap rule
# (0.3) took a circle for an open stroke in 23 of heldout-l3's 48 sweeps, this one in 3.
LOOP_ARC = 2.0
# A loop stroke is read by the distances of this many samples of it to its curve, their
# squares weighed by LOOP_WEIGHT: together they count as one open stroke's two ends (four
# squared residuals), for a loop starts anywhere and is lopsided, so its ends tell nothing.
LOOP_SAMPLES = 24
LOOP_WEIGHT = 4.0 / LOOP_SAMPLES


class FitError(ValueError):
    """The strokes do not describe an operation on this model; the message says why."""


def resample(polyline: np.ndarray, step: float = 1.0) -> np.ndarray:
    """Points every `step` pixels along a stroke (its ends included), (K, 2); a stroke of
    one point, or of no length, is that one point."""
    p = np.asarray(polyline, float)
    if len(p) < 2:
        return p[:1].copy()
    s = arc_lengths(p)
    return p[:1].copy() if s[-1] == 0 else resample_every(p, step, s)


def sample_map(img: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """Values of an (H, W) map at pixel positions (K, 2), nearest pixel, clamped to the image."""
    h, w = img.shape
    i = np.clip(np.floor(pts[:, 0]).astype(int), 0, w - 1)
    j = np.clip(np.floor(pts[:, 1]).astype(int), 0, h - 1)
    return img[j, i]


def classify_strokes(
    strokes: list[np.ndarray], curve: np.ndarray, thresholds: tuple[float, ...]
) -> list[int]:
    """Each stroke's class by counting (paper, "Add/subtract regression").

    A sample point of a stroke votes for class k when the curve map C there falls in
    the k-th interval cut by `thresholds` ((0.5,) for two classes, (0.5, 1.5) for
    three); the stroke takes the class with the most votes.
    """
    labels = []
    for s in strokes:
        vals = sample_map(curve, resample(s))
        cls = np.searchsorted(np.asarray(thresholds), vals, side="left")
        labels.append(int(np.bincount(cls, minlength=len(thresholds) + 1).argmax()))
    return labels


def is_loop(stroke: np.ndarray) -> bool:
    """Whether a stroke is a loop (a circle's), not a line or an arc with two ends: its
    length is over LOOP_ARC times its extent."""
    s = np.asarray(stroke, float)
    return len(s) <= 1 or bool(polyline_length(s) > LOOP_ARC * np.ptp(s, axis=0).max())


def open_ends(strokes: list[np.ndarray]) -> np.ndarray:
    """(S, 2, 2) the first and last points of the strokes that are not loops (`is_loop`)."""
    ends = [(s[0], s[-1]) for s in map(np.asarray, strokes) if not is_loop(s)]
    return np.array(ends, float).reshape(-1, 2, 2)


def loop_samples(stroke: np.ndarray, count: int = LOOP_SAMPLES) -> np.ndarray:
    """`count` points (count, 2) evenly along a loop stroke by arc length (its last
    point, near its first, left out)."""
    return resample_polyline(stroke, count + 1)[:-1]


def loop_distances(points: np.ndarray, loop: np.ndarray) -> np.ndarray:
    """Each point's distance (K,) to a closed polyline (M, 2)."""
    a, b = loop, np.roll(loop, -1, axis=0)
    ab = b - a
    t = np.clip(
        np.einsum("kmj,mj->km", points[:, None] - a[None], ab)
        / np.maximum((ab * ab).sum(axis=1), 1e-12),
        0.0,
        1.0,
    )
    near = a[None] + t[..., None] * ab[None]
    return np.linalg.norm(points[:, None] - near, axis=2).min(axis=1)


def match_ends(
    curve_ends: np.ndarray, stroke_ends: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Which open curve each open stroke draws, and which way: the one-to-one matching
    with the least sum of squared gaps between their ends (the hand the data generator
    models, datagen/strokes.py: a curve drawn as one stroke whose two ends miss the
    curve's by Gaussian noise, spread linearly along it).

    Args:
        curve_ends: (C, 2, 2) each open curve's first and last points, pixels.
        stroke_ends: (S, 2, 2) each open stroke's (`open_ends`).
    Returns:
        (strokes, curves, swapped): the matched indices, and whether each stroke runs
        from its curve's last point to its first.
    """
    if not len(curve_ends) or not len(stroke_ends):
        return np.zeros(0, int), np.zeros(0, int), np.zeros(0, bool)
    same = ((stroke_ends[:, None] - curve_ends[None]) ** 2).sum(axis=(2, 3))
    swapped = ((stroke_ends[:, None] - curve_ends[None, :, ::-1]) ** 2).sum(axis=(2, 3))
    rows, cols = linear_sum_assignment(np.minimum(same, swapped))
    return rows, cols, swapped[rows, cols] < same[rows, cols]


def end_order(swapped: np.ndarray) -> np.ndarray:
    """(M, 2) for each matched stroke (`match_ends`), which end of its curve (0 first,
    1 last) its first and its last point draw."""
    return np.where(np.asarray(swapped, bool)[:, None], [[1, 0]], [[0, 1]])


def stroke_pixels(strokes: list[np.ndarray], shape: tuple[int, int]) -> np.ndarray:
    """A boolean (H, W) map of the pixels the strokes pass through."""
    h, w = shape
    m = np.zeros(shape, bool)
    for s in strokes:
        q = resample(s, 0.5)
        i, j = np.floor(q[:, 0]).astype(int), np.floor(q[:, 1]).astype(int)
        ok = (i >= 0) & (i < w) & (j >= 0) & (j < h)
        m[j[ok], i[ok]] = True
    return m


class DistanceField:
    """Distance (pixels) from any image position to the nearest target pixel.

    Positions outside the image get the border value plus their distance to the
    image, so candidates leaving the frame are penalised smoothly.
    """

    def __init__(self, target: np.ndarray):
        if not target.any():
            raise FitError("no stroke pixels to match")
        # OpenCV's exact (DIST_MASK_PRECISE) Euclidean transform: scipy's equal to 1e-6 px,
        # 4x slower on a 256 x 256 map; one is made for every reading scored.
        self.dt = cv2.distanceTransform(
            (~target).astype(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE
        )
        self.h, self.w = target.shape

    def __call__(self, pts: np.ndarray) -> np.ndarray:
        """Distances at positions (..., 2), bilinear inside the image."""
        x, y = pts[..., 0] - 0.5, pts[..., 1] - 0.5  # pixel centres sit at +0.5
        xc, yc = np.clip(x, 0, self.w - 1), np.clip(y, 0, self.h - 1)
        outside = np.hypot(x - xc, y - yc)
        # the cell's lower corner, one short of the last row / column so that its four
        # corners are in the image (there the weight of the far ones is 1)
        x0 = np.minimum(xc.astype(np.intp), self.w - 2)
        y0 = np.minimum(yc.astype(np.intp), self.h - 2)
        fx, fy = xc - x0, yc - y0
        flat, i = self.dt.ravel(), y0 * self.w + x0  # flat indexing: the line search's hot spot
        a, b, c, d = flat[i], flat[i + 1], flat[i + self.w], flat[i + self.w + 1]
        val = (a + (b - a) * fx) * (1 - fy) + (c + (d - c) * fx) * fy
        return val + outside


SIDE_SAMPLES = np.linspace(0.15, 0.85, 8)  # along a side edge, away from its noisy ends


def line_search(
    points: np.ndarray,
    direction: np.ndarray,
    camera: OrthoCamera,
    field: DistanceField,
    candidates: np.ndarray,
    sides: tuple[np.ndarray, np.ndarray, DistanceField] | None = None,
    ends: np.ndarray | None = None,
    end_weight: float = 0.0,
) -> tuple[float, float]:
    """The offset t minimising the mean distance of projected (points + t * direction).

    `direction` is one vector (3,) or one per point (P, 3) (a curved face moves along
    its normal at each point). Every candidate is scored at once: points (P, 3) are
    projected once and shifted in the image by t times the projected direction
    (projection is linear). With `sides` = (corners (V, 3), their directions (V, 3) or
    (3,), field), the segments from each corner to the corner moved by t are scored
    against that field too, and the two means averaged. With `ends` too ((S, 2, 2), the
    open strokes' ends: `open_ends`), `end_weight` times how far the strokes' ends and
    the corners and moved corners lie from each other (mean nearest distance, both ways)
    is added: the hand misses a line's ends by noise it spreads along the stroke
    (`match_ends`), so the ends tell where the moved corners are.

    Returns:
        (best t refined between its neighbours by a parabola, its mean distance in px,
        the ends' term left out).
    """
    base, _ = camera.project(points)  # (P, 2)
    step2d = _images_of(camera, points, direction)  # (P or 1, 2) px per t
    pos = base[None, :, :] + candidates[:, None, None] * step2d  # (K, P, 2)
    scores = field(pos).mean(axis=1)  # (K,)
    ranked = scores
    if sides is not None:
        corners, corner_direction, side_field = sides
        c2d, _ = camera.project(corners)  # (V, 2)
        c_step = _images_of(camera, corners, corner_direction)  # (V or 1, 2)
        frac = candidates[:, None] * SIDE_SAMPLES[None, :]  # (K, S)
        spos = c2d[None, :, None, :] + frac[:, None, :, None] * c_step[None, :, None, :]
        ranked = scores = (scores + side_field(spos).mean(axis=(1, 2))) / 2
        if ends is not None and len(ends) and end_weight > 0:
            tips = ends.reshape(-1, 2)  # (E, 2)
            moved = c2d[None] + candidates[:, None, None] * c_step[None]  # (K, V, 2)
            drawn = np.concatenate([np.broadcast_to(c2d, moved.shape), moved], axis=1)
            gaps = np.linalg.norm(drawn[:, :, None] - tips[None, None], axis=3)  # (K, 2V, E)
            apart = (gaps.min(axis=2).mean(axis=1) + gaps.min(axis=1).mean(axis=1)) / 2
            ranked = scores + end_weight * apart
    k = int(np.argmin(ranked))
    t = float(candidates[k])
    if 0 < k < len(candidates) - 1:
        a, b, c = ranked[k - 1], ranked[k], ranked[k + 1]
        denom = a - 2 * b + c
        if denom > 1e-12:
            t += 0.5 * (a - c) / denom * float(candidates[k + 1] - candidates[k])
    return t, float(scores[k])


def _images_of(camera: OrthoCamera, points: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Pixel displacements of one direction (3,) -> (1, 2), or of one per point (P, 3)
    -> (P, 2)."""
    direction = np.asarray(direction, float)
    if direction.ndim == 1:
        return camera.image_of(direction)[None, :]
    return camera.project(points + direction)[0] - camera.project(points)[0]


def search_range(
    scale: float, lo: float = -1.5, hi: float = 1.5, step: float = 0.0075
) -> np.ndarray:
    """The paper's line-search candidates for a model of diagonal `scale` (mm)."""
    n = round((hi - lo) / step) + 1
    return np.linspace(lo, hi, n) * scale


def edge_samples(face: cq.Face, spacing: float) -> np.ndarray:
    """Points along all edges of a face, about `spacing` mm apart, (P, 3)."""
    pts = []
    for e in face.Edges():
        n = max(int(np.ceil(e.Length() / spacing)), 2)
        pts += [e.positionAt(t).toTuple() for t in np.linspace(0, 1, n)]
    return np.array(pts)


# Every way each unknown of `box_least_squares` may lie: free (0), at its lower bound (1)
# or at its upper one (2), per number of unknowns.
_ACTIVE_SETS: dict[int, np.ndarray] = {}


def box_least_squares(a: np.ndarray, b: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """The x minimising |a x - b| with lo <= x <= hi in every unknown, exactly, for a few
    unknowns (N, here 4): the minimum lies where each unknown is free or at one bound,
    so every one of the 3^N such active sets is solved at once (the free unknowns by the
    normal equations) and the feasible solution of least residual is the one. scipy's
    `lsq_linear` reaches it by iterations, eight times slower on four unknowns.

    Args:
        a: (M, N) the system; b: (M,) the target.
    Returns:
        (N,) the solution.
    """
    n = a.shape[1]
    if n not in _ACTIVE_SETS:
        _ACTIVE_SETS[n] = np.stack(np.meshgrid(*[np.arange(3)] * n, indexing="ij"), -1)
    sets = _ACTIVE_SETS[n].reshape(-1, n)  # (3^N, N)
    gram, atb = a.T @ a, a.T @ b
    fixed = sets > 0
    value = np.where(sets == 2, hi, lo).astype(float)
    # free rows: the normal equations; fixed rows: x_i = its bound
    m = np.where(fixed[:, :, None], np.eye(n)[None], gram[None])
    r = np.where(fixed, value, atb[None])
    # a free set the normal equations leave singular (a degenerate stroke) is passed over
    free = n - fixed.sum(axis=1)
    ok = np.abs(np.linalg.det(m)) > 1e-12 * max(float(np.abs(gram).max()), 1e-300) ** free
    x = np.zeros((len(sets), n))
    x[ok] = np.linalg.solve(m[ok], r[ok][..., None])[..., 0]
    slack = 1e-9 * max(abs(hi - lo), 1.0)
    feasible = ok & np.all((x >= lo - slack) & (x <= hi + slack), axis=1)
    residual = np.einsum("ki,ij,kj->k", x, gram, x) - 2 * x @ atb
    return np.clip(x[np.flatnonzero(feasible)[np.argmin(residual[feasible])]], lo, hi)


def fit_bezier(
    points: np.ndarray,
    start: np.ndarray,
    end: np.ndarray,
    iterations: int = 4,
    corner: np.ndarray | None = None,
    span: float = 1.0,
) -> np.ndarray:
    """A cubic Bezier from `start` to `end` fitting `points` (K, D) in least squares.

    The inner control points are solved linearly for chord-length parameters, which
    are then re-estimated by projecting the points onto the curve a few times. With a
    `corner` c (2D), each inner control point is kept in the parallelogram
    c + s (start - c) + t (end - c), s and t in [0, span] (a bounded least squares).

    Returns:
        (4, D) control points.
    """
    p = np.asarray(points, float)
    d = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])
    t = d / d[-1] if d[-1] > 0 else np.linspace(0, 1, len(p))
    ctrl = np.stack([start, start + (end - start) / 3, start + 2 * (end - start) / 3, end])
    for _ in range(iterations):
        b1, b2 = 3 * (1 - t) ** 2 * t, 3 * (1 - t) * t**2
        rhs = p - np.outer((1 - t) ** 3, start) - np.outer(t**3, end)
        a = np.stack([b1, b2], axis=1)
        if corner is None:
            sol, *_ = np.linalg.lstsq(a, rhs, rcond=None)
        else:  # unknowns (s1, t1, s2, t2); each point's residual is linear in them
            axes = np.stack([start - corner, end - corner])  # (2, D)
            basis = (a[:, :, None, None] * axes[None, None]).reshape(len(p), 4, -1)
            st = box_least_squares(
                basis.transpose(0, 2, 1).reshape(-1, 4),
                (rhs - (b1 + b2)[:, None] * corner).ravel(),
                0.0,
                span,
            )
            sol = corner + st.reshape(2, 2) @ axes
        ctrl = np.stack([start, sol[0], sol[1], end])
        dense_t = np.linspace(0, 1, 201)
        dense = bezier(ctrl, dense_t)
        nearest = np.argmin(((p[:, None, :] - dense[None]) ** 2).sum(-1), axis=1)
        t = np.maximum.accumulate(dense_t[nearest])  # keep the order along the stroke
    return ctrl
