# SPDX-License-Identifier: LGPL-2.1-or-later
"""Small numeric geometry shared by every layer (numpy only): cubic Beziers, an
orthonormal basis of a plane, and polylines resampled by arc length."""

import numpy as np


def bezier(ctrl: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Points (K, D) of a cubic Bezier with control points (4, D) at parameters t (K,)."""
    t = np.asarray(t, float)[:, None]
    return (
        (1 - t) ** 3 * ctrl[0]
        + 3 * (1 - t) ** 2 * t * ctrl[1]
        + 3 * (1 - t) * t**2 * ctrl[2]
        + t**3 * ctrl[3]
    )


def bezier_points(ctrl: np.ndarray, k: int) -> np.ndarray:
    """k points (K, D) of a cubic Bezier at evenly spaced parameters, both ends included."""
    return bezier(ctrl, np.linspace(0, 1, k))


def unit(v: np.ndarray) -> np.ndarray:
    """v / |v|."""
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def vec3(p) -> tuple[float, float, float]:
    """A 3D point or vector as a tuple of three floats (how operations hold them)."""
    return (float(p[0]), float(p[1]), float(p[2]))


def point_text(p: np.ndarray) -> str:
    """A point as errors show it: "(x, y, z)" to the micrometre, without "-0"."""
    return "(" + ", ".join(f"{round(float(x), 3) + 0.0:g}" for x in p) + ")"


def plane_basis(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """An orthonormal basis (u, v) of the plane with unit normal n, (u, v, n) right-handed;
    u is perpendicular to the x axis unless n is nearly along it (then to the y axis)."""
    u = np.cross(n, [1.0, 0, 0] if abs(n[0]) < 0.9 else [0, 1.0, 0])
    u /= np.linalg.norm(u)
    return u, np.cross(n, u)


def arc_lengths(points: np.ndarray) -> np.ndarray:
    """The arc length (K,) from a polyline's first point (K, D) to each of its points."""
    d = np.diff(points, axis=0)
    # np.linalg.norm's own sum of squares, without its overhead: strokes are resampled
    # a hundred times per interpret step
    return np.concatenate([[0.0], np.cumsum(np.sqrt((d * d).sum(axis=1)))])


def polyline_length(points: np.ndarray) -> float:
    """A polyline's (K, D) length."""
    return float(arc_lengths(np.asarray(points, float))[-1])


def resample_polyline(points: np.ndarray, count: int) -> np.ndarray:
    """`count` points (count, D) evenly spaced by arc length along a polyline (K, D) of
    at least two points, both ends included (linear between its points)."""
    p = np.asarray(points, float)
    return _at_lengths(p, arc_lengths(p), count)


def resample_every(
    points: np.ndarray, step: float, lengths: np.ndarray | None = None
) -> np.ndarray:
    """A polyline (K, D) of at least two points resampled every ~`step` of arc length
    (its units), both ends included: at least two points. `lengths`: its `arc_lengths`,
    when the caller has them."""
    p = np.asarray(points, float)
    s = arc_lengths(p) if lengths is None else lengths
    return _at_lengths(p, s, max(int(np.ceil(s[-1] / step)) + 1, 2))


def _at_lengths(p: np.ndarray, s: np.ndarray, count: int) -> np.ndarray:
    """`resample_polyline` of p (K, D) given its `arc_lengths` s."""
    t = np.linspace(0.0, s[-1], count)
    out = np.empty((count, p.shape[1]))
    for k in range(p.shape[1]):
        out[:, k] = np.interp(t, s, p[:, k])
    return out


def crossing_sides(polygon: np.ndarray) -> tuple[int, int] | None:
    """The first two non-adjacent sides (i, j), i < j, of a closed 2D polygon (K, 2) that
    properly cross each other, or None when none do (side i runs from vertex i to i + 1)."""
    k = len(polygon)
    for i in range(k):
        for j in range(i + 2, k):
            if i == 0 and j == k - 1:
                continue
            if _segments_cross(polygon[i], polygon[(i + 1) % k], polygon[j], polygon[(j + 1) % k]):
                return i, j
    return None


def _segments_cross(a, b, c, d) -> bool:
    def orient(p, q, r):
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])

    return orient(a, b, c) * orient(a, b, d) < 0 and orient(c, d, a) * orient(c, d, b) < 0
