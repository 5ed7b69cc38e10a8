# SPDX-License-Identifier: LGPL-2.1-or-later
"""Comparing solids: the volume IoU used by the end-to-end recovery rate.

Exact Booleans between two solids whose faces nearly coincide (a fitted bevel on top of
the true one) can fail silently in OCCT: the intersection of two solids that differ by
0.1% of their volume came back with volume -0.04 mm^3 and both cuts left their solid
whole, as if the solids were disjoint, so a near-perfect fit scored IoU 0 (the union
was right). So |A and B| is taken when the intersection and the union agree on it;
otherwise, or when the answer is low (the way such a failure shows), a point-sampling
estimate picks the route that agrees with it, and failing that, a finer sampling gives
the answer.
"""

from __future__ import annotations

from collections.abc import Callable

import cadquery as cq
import numpy as np

CHECK_POINTS = 512  # points of the sampling check (0.1 to 0.5 s for two solids)
FALLBACK_POINTS = 4000  # points of the sampled answer when no Boolean route holds
AGREE_VOLUME = 1e-4  # intersection and union agree within this share of the larger volume
CHECKED_BELOW = 0.5  # IoU below which a Boolean answer is checked by sampling
AGREE = 0.05  # largest IoU gap between a checked answer and the sampling
FUZZY = 1e-5  # fuzzy Boolean tolerance, as a share of the bounding diagonal
MESH_TOL = 1e-3  # the sampling's tessellation, as a share of the bounding diagonal
# The sampling's ray direction: off every axis, so that no ray runs along a box's face or
# through its edges, where a crossing would count twice or not at all.
RAY = np.array([0.8017837257, 0.5345224838, 0.2672612419])


def _inside(shape: cq.Shape, points: np.ndarray) -> np.ndarray:
    """Which points (K, 3) lie inside the solid: the parity of a ray's crossings of its
    tessellation (within MESH_TOL of the diagonal of its surface). OCCT's point
    classifier took up to 0.15 s a point on a swept solid (math_GlobOptMin on its
    B-spline edges), so one sampled IoU took 20 minutes."""
    box = shape.BoundingBox()
    vertices, triangles = shape.tessellate(MESH_TOL * box.DiagonalLength, 0.2)
    v = np.array([p.toTuple() for p in vertices])
    t = np.array(triangles, int).reshape(-1, 3)
    a, e1, e2 = v[t[:, 0]], v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]]
    h = np.cross(RAY, e2)  # Moller-Trumbore, every point's ray against every triangle
    det = np.einsum("ij,ij->i", e1, h)
    keep = np.abs(det) > 1e-12 * np.einsum("ij,ij->i", e1, e1)  # not edge-on to the ray
    a, e1, e2, h, inv = a[keep], e1[keep], e2[keep], h[keep], 1.0 / det[keep]
    out = np.empty(len(points), bool)
    for lo in range(0, len(points), 64):  # a few MB of (points, triangles) at a time
        s = np.asarray(points[lo : lo + 64], float)[:, None, :] - a[None]
        u = np.einsum("ptj,tj->pt", s, h) * inv
        q = np.cross(s, e1[None])
        w = (q @ RAY) * inv
        along = np.einsum("ptj,tj->pt", q, e2) * inv
        hits = (u >= 0) & (w >= 0) & (u + w <= 1) & (along > 0)
        out[lo : lo + 64] = np.count_nonzero(hits, axis=1) % 2 == 1
    return out


def sampled_iou(a: cq.Shape, b: cq.Shape, count: int, seed: int = 0) -> float:
    """IoU estimated from `count` points spread uniformly over both solids' bounding box."""
    box = a.BoundingBox().add(b.BoundingBox())
    rng = np.random.default_rng(seed)
    pts = rng.uniform((box.xmin, box.ymin, box.zmin), (box.xmax, box.ymax, box.zmax), (count, 3))
    ina, inb = _inside(a, pts), _inside(b, pts)
    union = int(np.count_nonzero(ina | inb))
    return float(np.count_nonzero(ina & inb) / union) if union else 0.0


def _common_routes(a: cq.Shape, b: cq.Shape, va: float, vb: float) -> list[Callable[[], float]]:
    """Ways to compute |A and B| with Booleans, cheapest and most exact first."""
    tol = FUZZY * a.BoundingBox().add(b.BoundingBox()).DiagonalLength
    return [
        lambda: a.intersect(b).Volume(),
        lambda: va + vb - a.fuse(b).Volume(),
        lambda: a.intersect(b, tol=tol).Volume(),
        lambda: va + vb - a.fuse(b, tol=tol).Volume(),
    ]


def volume_iou(a: cq.Shape, b: cq.Shape) -> float:
    """|A and B| / |A or B|, in 0..1 (1 for identical solids).

    |A or B| = |A| + |B| - |A and B|. |A and B| comes from the intersection when the
    union agrees with it (within AGREE_VOLUME) and the IoU is at least CHECKED_BELOW;
    otherwise from the first Boolean route (intersection, union, both fuzzy) that gives
    a possible value (0 <= |A and B| <= min(|A|, |B|)) within AGREE of a coarse
    sampling estimate; failing all, the IoU is estimated from FALLBACK_POINTS random
    points (about +-0.005 near 0.95 for solids filling half their box).
    """
    va, vb = a.Volume(), b.Volume()
    if va <= 0 or vb <= 0:
        return 0.0
    slack = AGREE_VOLUME * max(va, vb)

    def possible(route: Callable[[], float]) -> float | None:
        try:
            common = route()
        except Exception:  # an OCCT Boolean that gives up: the next route may not
            return None
        if not -slack <= common <= min(va, vb) + slack:
            return None
        return min(max(common, 0.0), min(va, vb))

    routes = _common_routes(a, b, va, vb)
    values = [possible(r) for r in routes[:2]]
    if None not in values and abs(values[0] - values[1]) <= slack:
        iou = values[0] / (va + vb - values[0])
        if iou >= CHECKED_BELOW:
            return float(iou)
    check = sampled_iou(a, b, CHECK_POINTS)
    for common in values + [possible(r) for r in routes[2:]]:
        if common is not None:
            iou = common / (va + vb - common)
            if abs(iou - check) <= AGREE:
                return float(iou)
    return sampled_iou(a, b, FALLBACK_POINTS, seed=1)
