# SPDX-License-Identifier: LGPL-2.1-or-later
"""Extrude regression: the offset d of face f by line search (paper, "Extrude regression")."""

from __future__ import annotations

import cadquery as cq
import numpy as np
from scipy.optimize import linear_sum_assignment, minimize_scalar

from ...brep.corners import line_edges
from ...brep.faces import CurvedSurface, FaceFrame, face_ref_at, face_ref_of, is_curved, model_scale
from ...brep.protocol import Extrude, FaceRef
from ...render.camera import OrthoCamera
from .common import (
    LOOP_WEIGHT,
    DistanceField,
    FitError,
    edge_samples,
    end_order,
    is_loop,
    line_search,
    loop_distances,
    loop_samples,
    match_ends,
    open_ends,
    search_range,
    stroke_pixels,
)

# Mean distance (px) between the moved face's edges and the offset strokes above which
# the strokes are not read as an extrusion of f.
EXTRUDE_MISMATCH_PX = 12.0
# Samples along f's edges at most (one per context pixel below that): the line search
# scores every candidate offset at every sample, so a face far larger than the context
# (its edges run far out of the frame) must not multiply its cost.
MAX_EDGE_SAMPLES = 4096
# Views closer than this to head-on (|cos| of the angle between n_f and the view) show
# no extrusion depth.
HEAD_ON_COS = 0.995
# A curved f may shrink by at most this share of its smallest radius: a cylinder
# shrunk to its axis is no solid (brep/operators refuses |d| >= the radius).
MAX_SHRINK = 0.95
# How much the strokes' ends count against the corners and moved corners in the line
# search (`line_search`): with 1, held-out extrusions read closer on average than with
# 0 or 0.3 (test-l1 mean volume IoU 0.957 -> 0.960; see docs/measurements.md,
# extrude.LINE_SEARCH_END_WEIGHT).
LINE_SEARCH_END_WEIGHT = 1.0
# A stroke whose ends lie farther than this (px, the root of the two ends' summed
# squares) from every line of the extrusion it could draw was drawn for something else
# (C mislabelled it, or it is no part of the extrusion): past it, it stops counting.
TIP_CAP_PX = 30.0
# Samples along a curved f's rim (a closed edge) for its distances to a loop stroke.
RIM_SAMPLES = 48
# Points of a curved f (around, along) among which p_f is chosen: 5 degrees apart.
REF_GRID = (73, 7)


def fit_extrude(
    solid: cq.Shape,
    face: cq.Face,
    camera: OrthoCamera,
    offset_strokes: list[np.ndarray],
    profile_strokes: list[np.ndarray] | None = None,
    end_weight: float = LINE_SEARCH_END_WEIGHT,
    at: float | None = None,
) -> Extrude:
    """Find d such that the edges of f moved by d * n_f match the offset-curve strokes.

    The paper matches the moved edges to the offset curve only; when side-edge strokes
    are given, the side edges from f's corners to the moved corners are matched to them
    too, which halves the effect of endpoint noise on d. On a curved f (a cylinder's or
    cone's side, beyond the paper) each edge point moves along f's normal there: the
    side's radius grows by d (shrinks for d < 0; a bore's wall narrows for d > 0), and
    f is named by the point of it that faces the viewer most.

    Args:
        solid: the context solid (sets the search range: -1.5..1.5 model diagonals,
            step 0.0075 diagonal, as in the paper).
        face: the base face f (planar, or a cylinder's or cone's side).
        camera: the context camera; strokes are in its pixels.
        offset_strokes: the strokes classified as the offset curve (C > 0.5).
        profile_strokes: the strokes classified as side edges (C <= 0.5), if any.
        end_weight: on a polygonal f, how much the strokes' ends count against the
            corners and moved corners (`line_search`; 0: closeness alone, as in the
            paper).
        at: d found otherwise (`fit_extrude_by_ends`): only its mismatch is checked.
    Raises:
        FitError: no offset strokes, a head-on view of a planar f, or no offset matches
            the strokes.
    Returns:
        The Extrude operation on f.
    """
    if not offset_strokes:
        raise FitError("extrude: no stroke was recognised as the moved face's outline")
    curved = is_curved(face)
    if not curved and abs(float(FaceFrame.of(face).normal @ camera.basis()[2])) > HEAD_ON_COS:
        raise FitError(
            "extrude: the face is seen head-on, so its offset cannot be read; turn the view"
        )
    scale = model_scale(solid)
    field = DistanceField(stroke_pixels(offset_strokes, (camera.height, camera.width)))
    perimeter = sum(e.Length() for e in face.Edges())
    points = edge_samples(face, spacing=max(camera.pixel_size, perimeter / MAX_EDGE_SAMPLES))
    corners = np.array([v.toTuple() for v in face.Vertices()])
    cands = search_range(scale)
    if curved:
        surface = CurvedSurface.of(face)
        direction, corner_direction = surface.normals(points), surface.normals(corners)
        cands = _within_shrink(cands, surface, points)
    else:
        direction = corner_direction = FaceFrame.of(face).normal
    cands = cands[np.abs(cands) > 1e-9] if at is None else np.array([at])  # d = 0: no op
    sides = None
    if profile_strokes and len(corners):
        sides = (
            corners,
            corner_direction,
            DistanceField(stroke_pixels(profile_strokes, (camera.height, camera.width))),
        )
    # the strokes' ends lie at corners only where f's outline is a polygon (a disk's
    # outline is one loop, its sides are silhouettes ending nowhere near its seam vertex)
    polygon = all(e.geomType() == "LINE" for e in face.Edges())
    drawn = offset_strokes + [
        s for s in profile_strokes or () if not any(s is o for o in offset_strokes)
    ]
    d, err = line_search(
        points,
        direction,
        camera,
        field,
        cands,
        sides,
        open_ends(drawn) if polygon else None,
        end_weight,
    )
    if err > EXTRUDE_MISMATCH_PX:
        raise FitError(
            f"extrude: no offset of the face matches the strokes (closest is "
            f"{err:.1f} px off on average)"
        )
    if abs(d) < 1e-6 * scale:
        raise FitError("extrude: the strokes lie on the face itself (offset 0)")
    return Extrude(_facing_ref(face, camera) if curved else face_ref_of(face), float(d))


def _within_shrink(cands: np.ndarray, surface: CurvedSurface, points: np.ndarray) -> np.ndarray:
    """The candidate offsets that shrink the side (points of it) by less than MAX_SHRINK
    of its smallest radius (a cone's narrow end)."""
    radius = float(np.min(surface.radius_at(points)))
    return cands[cands * (1 if surface.convex else -1) > -MAX_SHRINK * radius]


def _facing_ref(face: cq.Face, camera: OrthoCamera) -> FaceRef:
    """A curved f named at the point of it that faces the viewer most: any point of f
    names it, and this one is where the designer sees it."""
    u0, u1, v0, v1 = face.uvBounds()
    adaptor = face._geomAdaptor()
    grid = np.array(
        [
            adaptor.Value(u, v).Coord()
            for u in np.linspace(u0, u1, REF_GRID[0])
            for v in np.linspace(v0, v1, REF_GRID[1])[1:-1]
        ]
    )  # off the rims
    facing = CurvedSurface.of(face).normals(grid) @ np.asarray(camera.basis()[2], float)
    return face_ref_at(face, grid[int(np.argmin(facing))])


def _curved_by_ends(
    solid: cq.Shape, face: cq.Face, camera: OrthoCamera, strokes: list[np.ndarray]
) -> Extrude | None:
    """d of a curved f's radial offset from what the hand leaves of its strokes, as the
    session oracle reads it (training/session_oracle.py): an open stroke (the seam, a
    side edge at a corner) by its two ends, each paired with the open curve whose ends
    fit its own (`match_ends`), and a loop (a moved rim) by the distances of its samples
    to the rim it lies closest to, weighed as two ends. Every point of the moved curves
    is p + d n(p), linear in d, so each candidate d (the line search's range) is scored
    cheaply; the best is polished by a bounded scalar search. Closeness along an open
    stroke follows the hand's miss (the pipe session's step 2: +1 mm read as -0.67 by
    closeness, +0.79 so). Kept for the level-1 hand, though at level 3 the side edges
    at the seam's corners pair badly. None when no stroke pairs with a curve."""
    surface = CurvedSurface.of(face)
    # open curves: a seam edge (both ends move with d), a side edge from each corner
    # to its moved copy (its first end stays); rims: the closed edges, moving with d
    opened, moves, rims = [], [], []
    for edge in face.Edges():
        if edge.IsClosed():
            rims.append(
                np.array(
                    [
                        edge.positionAt(t).toTuple()
                        for t in np.linspace(0, 1, RIM_SAMPLES, endpoint=False)
                    ]
                )
            )
        else:
            opened.append([edge.positionAt(t).toTuple() for t in (0.0, 1.0)])
            moves.append((1.0, 1.0))
    for v in face.Vertices():
        opened.append([v.toTuple()] * 2)
        moves.append((0.0, 1.0))
    ends, loops = open_ends(strokes), [loop_samples(s) for s in strokes if is_loop(s)]
    if not (len(ends) and opened) and not (loops and rims):
        return None

    def image(pts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Images (K, 2) of points of f and their move per mm of d (K, 2)."""
        at = camera.project(pts)[0]
        return at, camera.project(pts + surface.normals(pts))[0] - at

    line_at, line_by = (np.zeros((0, 2, 2)),) * 2
    if opened:
        at, by = image(np.array(opened, float).reshape(-1, 3))
        line_at = at.reshape(-1, 2, 2)
        line_by = by.reshape(-1, 2, 2) * np.array(moves)[..., None]
    rim_images = [image(p) for p in rims]

    def cost(d: float) -> float:
        total = 0.0
        if len(ends) and len(line_at):
            curve_ends = line_at + d * line_by
            r, c, swapped = match_ends(curve_ends, ends)
            total += float(((curve_ends[c[:, None], end_order(swapped)] - ends[r]) ** 2).sum())
        if loops and rims:
            dist = np.array(
                [
                    [(loop_distances(q, at + d * by) ** 2).sum() for at, by in rim_images]
                    for q in loops
                ]
            )
            r, c = linear_sum_assignment(dist)
            total += LOOP_WEIGHT * float(dist[r, c].sum())
        return total

    edge_points = np.concatenate(rims + [np.array(opened, float).reshape(-1, 3)])
    cands = _within_shrink(search_range(model_scale(solid)), surface, edge_points)
    cands = cands[np.abs(cands) > 1e-9]
    if not len(cands):
        return None
    scores = [cost(float(d)) for d in cands]
    k = int(np.argmin(scores))
    lo, hi = cands[max(k - 1, 0)], cands[min(k + 1, len(cands) - 1)]
    d = (
        float(minimize_scalar(cost, bounds=(lo, hi), method="bounded").x)
        if hi > lo
        else float(cands[k])
    )
    if abs(d) < 1e-6 * model_scale(solid):
        return None
    return Extrude(_facing_ref(face, camera), d)


def offset_from_ends(tips: np.ndarray, corners_px: np.ndarray, step: np.ndarray) -> float:
    """The least-squares d (mm) of tips (k, 2) drawn at moved corners c_i + d * step,
    given their corners' images (k, 2) and the image of n_f (2,; px per mm)."""
    return float(((tips - corners_px) @ step).sum() / (len(tips) * (step @ step)))


def fit_extrude_by_ends(
    solid: cq.Shape,
    face: cq.Face,
    camera: OrthoCamera,
    offset_strokes: list[np.ndarray],
    profile_strokes: list[np.ndarray],
) -> Extrude | None:
    """d from the strokes' ends, each stroke read as the line it draws: a side edge from a
    corner c_i of f to its moved copy c_i + d n_f, an offset stroke from one moved corner
    to the next along f's outline.

    The hand the generator models (datagen/strokes.py) moves a stroke's two ends by
    independent Gaussians and spreads the move along it, so the ends hold what the stroke
    tells of d, and least squares on the ends at moved corners is d's likeliest value
    (training/extrusion_bound.py: the same estimate given the true pairing). Each stroke
    takes the line that fits its ends best at every candidate d (search_range, its cost
    capped at TIP_CAP_PX); at the best d the pairing is fixed and d solved in closed form,
    twice more with the pairing renewed. Beyond the paper's line search, which matches
    the moved outline to the strokes' pixels (docs/measurements.md, "Extrusions read from
    their strokes' ends").

    On a curved f (a cylinder's or cone's side) the moved rims are loops: `_curved_by_ends`.

    Returns:
        The Extrude on a curved f, or on a planar f whose outline is a polygon; or None
        (a disk, no offset stroke, a view along f, or no stroke within the cap). An
        outline with arcs is left to the line search: its curved sides draw silhouettes
        that end nowhere near a corner.
    """
    if is_curved(face):
        return _curved_by_ends(solid, face, camera, offset_strokes + profile_strokes)
    if not offset_strokes or not all(e.geomType() == "LINE" for e in face.Edges()):
        return None
    corners = np.array([v.toTuple() for v in face.Vertices()])
    step = camera.image_of(FaceFrame.of(face).normal)
    if step @ step < 1e-12:
        return None
    index_of = {tuple(np.round(c, 6)): i for i, c in enumerate(corners)}
    edges = np.array(
        [
            (index_of[tuple(np.round(a, 6))], index_of[tuple(np.round(b, 6))])
            for a, b in line_edges(face)
        ]
    )
    c2d = camera.project(corners)[0]
    sides = np.array([(q[0], q[-1]) for q in profile_strokes], float).reshape(-1, 2, 2)
    outline = np.array([(q[0], q[-1]) for q in offset_strokes], float).reshape(-1, 2, 2)
    cap = TIP_CAP_PX**2

    def sq(points: np.ndarray, tips: np.ndarray) -> np.ndarray:
        """Squared distances (..., V, S) of points (..., V, 2) to tips (S, 2)."""
        return ((points[..., :, None, :] - tips[None, :, :]) ** 2).sum(-1)

    def costs(d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Per candidate d (K,): each stroke's best cost (K, S) and the index of its
        best (line, direction) pairing (K, S), sides then outline strokes."""
        moved = c2d[None] + d[:, None, None] * step  # (K, V, 2)
        base = sq(c2d, sides[:, 0])[None], sq(c2d, sides[:, 1])[None]  # (1, V, S)
        up = sq(moved, sides[:, 1]), sq(moved, sides[:, 0])  # (K, V, S)
        side = np.concatenate([base[0] + up[0], base[1] + up[1]], axis=1)  # (K, 2V, S)
        i, j = edges[:, 0], edges[:, 1]
        a, b = sq(moved, outline[:, 0]), sq(moved, outline[:, 1])  # (K, V, S)
        line = np.concatenate([a[:, i] + b[:, j], a[:, j] + b[:, i]], axis=1)  # (K, 2E, S)
        return (
            np.concatenate([side.min(1), line.min(1)], axis=1),
            np.concatenate([side.argmin(1), line.argmin(1)], axis=1),
        )

    cands = search_range(model_scale(solid))
    d = float(cands[int(np.argmin(np.minimum(costs(cands)[0], cap).sum(1)))])
    v, e = len(corners), len(edges)
    for _ in range(3):  # closed form on the pairing at d, then pair again
        cost, pick = (x[0] for x in costs(np.array([d])))
        tips, owners = [], []
        for k, (c, p) in enumerate(zip(cost, pick, strict=False)):
            if c > cap:
                continue
            if k < len(sides):  # the end drawn at the moved corner
                tips.append(sides[k, 1] if p < v else sides[k, 0])
                owners.append(p % v)
            else:
                tips += list(outline[k - len(sides)])  # its two ends, along the edge or back
                owners += list(edges[p] if p < e else edges[p - e][::-1])
        if not tips:
            return None
        d = offset_from_ends(np.array(tips), c2d[owners], step)
    if abs(d) < 1e-6 * model_scale(solid):
        return None
    return Extrude(face_ref_of(face), d)
