# SPDX-License-Identifier: LGPL-2.1-or-later
"""Fitting N-gons to sketched outlines in the image (paper: ICP from profile end points)."""

from __future__ import annotations

import numpy as np

from ...brep.geometry import crossing_sides
from .common import FitError, resample


def order_around_centre(pts: np.ndarray) -> np.ndarray:
    """Points sorted by angle about their centroid: a simple polygon for convex shapes."""
    c = pts.mean(axis=0)
    return pts[np.argsort(np.arctan2(pts[:, 1] - c[1], pts[:, 0] - c[0]))]


def fit_polygon(initial: np.ndarray, strokes: list[np.ndarray], iterations: int = 5) -> np.ndarray:
    """Refine an N-gon to the stroke points, starting from `initial` (N, 2) vertices.

    Each round assigns every stroke sample to its nearest side, fits a line to each
    side's samples (its principal axis), and moves each vertex to where its two sides'
    lines meet. Vertices whose lines are nearly parallel, or sides with too few samples,
    keep their previous position.
    """
    poly = order_around_centre(np.asarray(initial, float))
    n = len(poly)
    if not strokes:
        return poly
    pts = np.concatenate([resample(s) for s in strokes])
    for _ in range(iterations):
        # every sample against every side at once: the nearest point of the side
        ab = np.roll(poly, -1, axis=0) - poly  # (N, 2)
        rel = pts[:, None, :] - poly[None]  # (M, N, 2)
        t = np.clip(
            np.einsum("mnk,nk->mn", rel, ab) / np.maximum((ab * ab).sum(1), 1e-12), 0.0, 1.0
        )
        gap = rel - t[..., None] * ab[None]
        side = np.einsum("mnk,mnk->mn", gap, gap).argmin(axis=1)
        # each side's line: its samples' centroid and principal axis, from their 2 x 2
        # covariance in closed form (the axis at angle atan2(2 sxy, sxx - syy) / 2)
        count = np.bincount(side, minlength=n)
        has = count >= 3
        mean = (
            np.stack([np.bincount(side, pts[:, k], n) for k in (0, 1)], 1)
            / np.maximum(count, 1)[:, None]
        )
        q = pts - mean[side]
        sxx, syy, sxy = (
            np.bincount(side, w, n) for w in (q[:, 0] ** 2, q[:, 1] ** 2, q[:, 0] * q[:, 1])
        )
        angle = 0.5 * np.arctan2(2 * sxy, sxx - syy)
        axis = np.stack([np.cos(angle), np.sin(angle)], 1)
        # vertex i where sides i - 1 and i meet (c0 + s a0 = c1 + r a1), unless either has
        # too few samples or they lie within ~9 degrees of parallel (|a0 x a1| < 0.15)
        a0, c0 = np.roll(axis, 1, axis=0), np.roll(mean, 1, axis=0)
        cross = a0[:, 0] * axis[:, 1] - a0[:, 1] * axis[:, 0]
        ok = has & np.roll(has, 1) & (np.abs(cross) >= 0.15)
        w = mean - c0
        s = (w[:, 0] * axis[:, 1] - w[:, 1] * axis[:, 0]) / np.where(ok, cross, 1.0)
        poly = np.where(ok[:, None], c0 + s[:, None] * a0, poly)
    return poly


def is_simple(poly: np.ndarray) -> bool:
    """True when no two non-adjacent sides of the polygon cross."""
    return crossing_sides(poly) is None


def profile_ends(
    profile_strokes: list[np.ndarray],
    start_strokes: list[np.ndarray],
    end_strokes: list[np.ndarray],
) -> tuple[np.ndarray, np.ndarray]:
    """Split the profile strokes' end points into the start set and the end set.

    Of each profile stroke's two ends, the one nearer to the start outline's samples
    (relative to its distance to the end outline) joins the start set.
    """
    if not start_strokes or not end_strokes:
        raise FitError("both the start and the end outline must be drawn")
    sp = np.concatenate([resample(s) for s in start_strokes])
    ep = np.concatenate([resample(s) for s in end_strokes])

    def gap(p, cloud):
        return float(np.min(np.linalg.norm(cloud - p, axis=1)))

    starts, ends = [], []
    for s in profile_strokes:
        a, b = np.asarray(s[0], float), np.asarray(s[-1], float)
        if gap(a, sp) + gap(b, ep) <= gap(b, sp) + gap(a, ep):
            starts.append(a)
            ends.append(b)
        else:
            starts.append(b)
            ends.append(a)
    return np.array(starts), np.array(ends)


def side_corners(side_strokes: list[np.ndarray], reach: float | None = None) -> np.ndarray:
    """The corners (N, 2) of an outline drawn one stroke per side, each corner the middle
    of the two stroke ends that meet there, ordered around their centre. Each stroke's end
    is joined to the nearest free end of another stroke, closest pairs first; or, with
    `reach`, the strokes must close into one loop, each corner's two ends within `reach`
    pixels of each other (an outline drawn whole, not strokes that merely pair up), the
    loop with the least total gap.

    Raises:
        FitError: fewer than 3 sides, or ends that do not pair up into a closed outline.
    """
    if len(side_strokes) < 3:
        raise FitError("an outline needs at least 3 sides drawn to give its corners")
    ends = np.array([(s[0], s[-1]) for s in map(np.asarray, side_strokes)], float)
    if reach is not None:
        return order_around_centre(_loop_corners(ends, reach))
    ends = ends.reshape(-1, 2)
    owner = np.repeat(np.arange(len(side_strokes)), 2)
    gap = np.linalg.norm(ends[:, None] - ends[None], axis=2)
    gap[owner[:, None] == owner[None]] = np.inf  # a side's own two ends are no corner
    corners, free = [], np.ones(len(ends), bool)
    for flat in np.argsort(gap, axis=None):
        i, j = np.unravel_index(flat, gap.shape)
        if not np.isfinite(gap[i, j]):
            break
        if free[i] and free[j]:
            free[i] = free[j] = False
            corners.append((ends[i] + ends[j]) / 2)
    if free.any():
        raise FitError("the outline's sides do not meet end to end")
    return order_around_centre(np.array(corners))


def stroke_loops(
    ends: np.ndarray, reach: float, sizes: tuple[int, int], budget: int | None = None
) -> list[tuple[list[int], list[int]]]:
    """The loops of strokes meeting end to end: each as (its strokes, the end each is
    entered by), its consecutive strokes' ends within `reach` pixels, of sizes[0] to
    sizes[1] strokes; each loop once from its lowest stroke (twice, by its two
    directions). The search gives up after `budget` steps (None: none).

    Args:
        ends: (K, 2, 2) each stroke's two end points.
    """
    k = len(ends)
    meets = {  # stroke i's end a meets stroke j's end b
        (i, a): [
            (j, b)
            for j in range(k)
            if j != i
            for b in (0, 1)
            if np.linalg.norm(ends[i, a] - ends[j, b]) <= reach
        ]
        for i in range(k)
        for a in (0, 1)
    }
    found: list[tuple[list[int], list[int]]] = []
    left = [np.inf if budget is None else budget]

    def walk(path: list[int], entered: list[int]) -> None:
        for j, b in meets[(path[-1], 1 - entered[-1])]:
            left[0] -= 1
            if left[0] < 0:
                return
            if j == path[0] and b == entered[0] and len(path) >= sizes[0]:
                found.append((path, entered))
            elif j > path[0] and j not in path and len(path) < sizes[1]:
                walk([*path, j], [*entered, b])

    for i in range(k):
        walk([i], [0])
    return found


def loop_gaps(ends: np.ndarray, path: list[int], entered: list[int]) -> np.ndarray:
    """Each corner's gap (pixels) in a loop of `stroke_loops`: from the end a stroke is
    left by to the end the next one is entered by."""
    into = np.array([ends[i, e] for i, e in zip(path, entered, strict=True)])
    out = np.array([ends[i, 1 - e] for i, e in zip(path, entered, strict=True)])
    return np.linalg.norm(into - np.roll(out, 1, axis=0), axis=1)


def _loop_corners(ends: np.ndarray, reach: float) -> np.ndarray:
    """The corners (the middles of the ends that meet) of the loop through every stroke
    (`ends`: (K, 2, 2)) whose consecutive strokes meet within `reach`, of least total
    gap.

    Raises:
        FitError: no such loop.
    """
    loops = stroke_loops(ends, reach, (len(ends), len(ends)))
    if not loops:
        raise FitError("the outline's sides do not meet end to end")
    path, entered = min(loops, key=lambda loop: float(loop_gaps(ends, *loop).sum()))
    into = np.array([ends[i, e] for i, e in zip(path, entered, strict=True)])
    out = np.array([ends[i, 1 - e] for i, e in zip(path, entered, strict=True)])
    return (into + np.roll(out, 1, axis=0)) / 2
