# SPDX-License-Identifier: LGPL-2.1-or-later
"""Curve-level regularization (paper, "Regularization"): snapping and rectification.

Everything here works in 2D coordinates of the base face's plane (mm). Thresholds are
the paper's: key points snap within 10% of the face diameter; parallelism and equal
corner angles are enforced within 20 degrees; equal side lengths within 20% of the mean.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SNAP_FRACTION = 0.10
ANGLE_TOL_DEG = 20.0
LENGTH_TOL = 0.20


@dataclass(frozen=True)
class FaceOutline:
    """The base face in its plane's 2D frame: corners, straight-edge directions, centre."""

    corners: np.ndarray        # (K, 2) vertices of f
    edge_dirs: np.ndarray      # (E, 2) unit directions of f's straight edges
    midpoints: np.ndarray      # (E, 2) midpoints of f's straight edges
    center: np.ndarray         # (2,) centroid of f
    diameter: float            # largest distance between two corners, mm

    def key_points(self) -> np.ndarray:
        """Corners, edge midpoints and the centre: where sketched primitives snap."""
        return np.concatenate([self.corners, self.midpoints, self.center[None]])


def snap_point(p: np.ndarray, outline: FaceOutline) -> np.ndarray:
    """The nearest key point of f if within 10% of f's diameter, else p itself."""
    keys = outline.key_points()
    dist = np.linalg.norm(keys - p, axis=1)
    k = int(np.argmin(dist))
    return keys[k].copy() if dist[k] <= SNAP_FRACTION * outline.diameter else p


def snap_polygon(poly: np.ndarray, outline: FaceOutline) -> np.ndarray:
    """Translate a polygon so its centre or one of its corners meets the nearest key point.

    Of all (polygon point, key point) pairs within the snapping distance, the closest
    pair decides the translation; the shape is unchanged.
    """
    ours = np.concatenate([poly.mean(axis=0)[None], poly])
    keys = outline.key_points()
    dist = np.linalg.norm(ours[:, None] - keys[None], axis=2)
    i, k = np.unravel_index(np.argmin(dist), dist.shape)
    if dist[i, k] > SNAP_FRACTION * outline.diameter:
        return poly
    return poly + (keys[k] - ours[i])


def _angles(poly: np.ndarray) -> np.ndarray:
    """Interior angles (degrees) of a simple polygon, any orientation."""
    n = len(poly)
    out = []
    for i in range(n):
        a, b = poly[i - 1] - poly[i], poly[(i + 1) % n] - poly[i]
        cos = a @ b / (np.linalg.norm(a) * np.linalg.norm(b))
        out.append(np.degrees(np.arccos(np.clip(cos, -1, 1))))
    return np.array(out)


def _sides(poly: np.ndarray) -> np.ndarray:
    return np.linalg.norm(np.roll(poly, -1, axis=0) - poly, axis=1)


def _orientation(poly: np.ndarray) -> float:
    """Angle (radians) of the polygon's first side."""
    d = poly[1] - poly[0]
    return float(np.arctan2(d[1], d[0]))


def _ccw(poly: np.ndarray) -> bool:
    x, y = poly[:, 0], poly[:, 1]
    return float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)) > 0


def equalize(poly: np.ndarray) -> np.ndarray:
    """Rectify a sketched N-gon: equal corner angles and, where close, equal sides.

    Quadrilaterals with corners within 20 degrees of 90 become rectangles (squares when
    the sides are within 20% too); other N-gons become regular when both their angles and
    sides are close. The centre and the first side's direction are kept.
    """
    n = len(poly)
    target = (n - 2) * 180.0 / n
    if np.max(np.abs(_angles(poly) - target)) > ANGLE_TOL_DEG:
        return poly
    sides = _sides(poly)
    equal_sides = np.max(np.abs(sides - sides.mean())) <= LENGTH_TOL * sides.mean()
    if n != 4 and not equal_sides:
        return poly
    theta = _orientation(poly)
    sign = 1.0 if _ccw(poly) else -1.0
    center = poly.mean(axis=0)
    if n == 4:
        a = (sides[0] + sides[2]) / 2
        b = (sides[1] + sides[3]) / 2
        if equal_sides:
            a = b = (a + b) / 2
        local = np.array([[-a / 2, -sign * b / 2], [a / 2, -sign * b / 2],
                          [a / 2, sign * b / 2], [-a / 2, sign * b / 2]])
    else:
        radius = sides.mean() / (2 * np.sin(np.pi / n))
        # First side along +x, on the side of the centre that keeps the orientation.
        ang = sign * (-np.pi / 2 - np.pi / n + 2 * np.pi * np.arange(n) / n)
        local = radius * np.stack([np.cos(ang), np.sin(ang)], axis=1)
    rot = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])
    return local @ rot.T + center


def align_to_edges(poly: np.ndarray, outline: FaceOutline) -> np.ndarray:
    """Rotate the polygon about its centre so that its side closest in direction to
    an edge of f becomes parallel to it, when within 20 degrees."""
    if len(outline.edge_dirs) == 0:
        return poly
    sides = np.roll(poly, -1, axis=0) - poly
    sang = np.arctan2(sides[:, 1], sides[:, 0])
    eang = np.arctan2(outline.edge_dirs[:, 1], outline.edge_dirs[:, 0])
    diff = (eang[None, :] - sang[:, None] + np.pi / 2) % np.pi - np.pi / 2  # mod 180 deg
    i, j = np.unravel_index(np.argmin(np.abs(diff)), diff.shape)
    delta = float(diff[i, j])
    if abs(np.degrees(delta)) > ANGLE_TOL_DEG:
        return poly
    c = poly.mean(axis=0)
    rot = np.array([[np.cos(delta), -np.sin(delta)], [np.sin(delta), np.cos(delta)]])
    return (poly - c) @ rot.T + c


def regularize_polygon(poly: np.ndarray, outline: FaceOutline) -> np.ndarray:
    """Equalize, then align with f's edges, then snap to f's key points."""
    return snap_polygon(align_to_edges(equalize(poly), outline), outline)
