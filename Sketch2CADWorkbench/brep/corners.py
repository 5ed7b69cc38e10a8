# SPDX-License-Identifier: LGPL-2.1-or-later
"""Where a bevel can round: the corners of a planar face f and the creases leaving them.

A crease is a straight edge of the solid running from a point of f into the solid along
-n_f (perpendicular to f); a bevel rounds a convex corner c of f, where two straight
edges of f meet, along the crease c -> c'. Points are world millimetres.
"""

from __future__ import annotations

from dataclasses import dataclass

import cadquery as cq
import numpy as np

from .faces import inside_face

# A straight edge runs along -n_f when the cosine of its angle with -n_f exceeds this.
CREASE_COS = 0.999


def line_edges(shape: cq.Shape) -> list[tuple[np.ndarray, np.ndarray]]:
    """The two end points of each straight edge of a shape (a face or a solid)."""
    return [
        (np.array(e.startPoint().toTuple()), np.array(e.endPoint().toTuple()))
        for e in shape.Edges()
        if e.geomType() == "LINE"
    ]


def creases(solid: cq.Shape, normal: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """Every straight edge of the solid that runs along -normal, as (start, end) with
    end - start along -normal, in the solid's edge order."""
    out = []
    for p, q in line_edges(solid):
        length = np.linalg.norm(q - p)
        for s, t in ((p, q), (q, p)):
            if float((t - s) @ normal) < -CREASE_COS * length:
                out.append((s, t))
    return out


def crease_end(
    solid: cq.Shape, corner: np.ndarray, normal: np.ndarray, tol: float
) -> np.ndarray | None:
    """c': the far end of the crease leaving `corner` (within tol) along -normal, or None
    when no straight edge of the solid does."""
    return next((t for s, t in creases(solid, normal) if np.linalg.norm(s - corner) < tol), None)


@dataclass(frozen=True)
class BevelCorner:
    """A convex corner c of face f with a straight crease c -> c' along -n_f.

    `a` and `b` are the unit directions of f's two edges leaving c, `la` and `lb`
    their lengths (mm).
    """

    c: np.ndarray
    opposite: np.ndarray
    a: np.ndarray
    b: np.ndarray
    la: float
    lb: float


def bevel_corners(solid: cq.Shape, face: cq.Face, n: np.ndarray, tol: float) -> list[BevelCorner]:
    """The corners of f that a bevel can round.

    A corner qualifies when two straight edges of f meet at c (within tol) at an angle
    below 180 degrees inside f (convex), and a crease of the solid leaves c.
    """
    edges = line_edges(face)
    out = []
    for c, cp in creases(solid, n):
        legs = [
            b - a if np.linalg.norm(a - c) < tol else a - b
            for a, b in edges
            if min(np.linalg.norm(a - c), np.linalg.norm(b - c)) < tol
        ]
        if len(legs) != 2:
            continue
        la, lb = (float(np.linalg.norm(v)) for v in legs)
        a, b = legs[0] / la, legs[1] / lb
        if abs(float(np.cross(a, b) @ n)) < 1e-3:  # straight through, or folded back
            continue
        bisector = (a + b) / np.linalg.norm(a + b) if np.linalg.norm(a + b) > 1e-9 else None
        if bisector is None or not inside_face(face, c + 1e-3 * min(la, lb) * bisector):
            continue  # reflex corner: the short way between the edges is outside f
        out.append(BevelCorner(c, cp, a, b, la, lb))
    return out


def corner_at(corners: list[BevelCorner], point: np.ndarray, tol: float) -> BevelCorner | None:
    """The corner at `point` (within tol), if one of them is."""
    return next((k for k in corners if np.linalg.norm(k.c - point) < tol), None)


def corner_along(
    corners: list[BevelCorner],
    point: np.ndarray,
    a: np.ndarray,
    b: np.ndarray,
    crease: float,
    tol: float,
) -> BevelCorner | None:
    """The corner nearest to `point` whose two edges leave it along the unit directions a
    and b (either way round, within CREASE_COS) and whose crease is `crease` mm long
    (within tol), with its edges in that order; None when no corner is such.

    This finds a corner again after an earlier step moved it: the corner keeps the
    directions of its edges (what a bevel's profile runs along) and its crease, while
    its place and its edges' lengths change.
    """
    best = None
    for k in corners:
        if abs(float(np.linalg.norm(k.opposite - k.c)) - crease) > tol:
            continue
        for ka, kb, la, lb in ((k.a, k.b, k.la, k.lb), (k.b, k.a, k.lb, k.la)):
            if float(ka @ a) > CREASE_COS and float(kb @ b) > CREASE_COS:
                d = float(np.linalg.norm(k.c - point))
                if best is None or d < best[0]:
                    best = (d, BevelCorner(k.c, k.opposite, ka, kb, la, lb))
    return None if best is None else best[1]
