# SPDX-License-Identifier: LGPL-2.1-or-later
"""Shell (beyond the paper): the wall thickness t read from the rim drawn on the face to
open.

The designer draws, on the face f to open, the inner rim the walls leave: f's outline
inset by t, as one loop or one stroke per side (a loop is cut at its corners before it
gets here: sketch/segment.py). A stroke down an inner wall from a corner of the rim may
follow; it says nothing more and is set aside.

    rim_and_wall(strokes) -> RimStrokes       which strokes draw the rim, which the wall
    shell_fit(solid, face, camera, rim) -> Shell
    thickest_that_builds(solid, face, op) -> Shell   t within what the solid takes

The strokes are a rim when they close into one loop: their ends, each paired with the
end nearest it where that end's nearest is it in turn, chain every stroke into it, but
for one stroke with a free end whose other end meets a corner (the wall). A prism's
outline with its depth lines has three strokes at each corner, so ends are left over
and it is not read as a rim.

t is where the rim lies. A first t is the median distance of the rim's samples,
back-projected onto f's plane, from f's outline (robust to the hand's wobble). It is
then fitted where the hand's error is measured, in the view's pixels: the t whose inset
outline, projected, and the strokes lie closest both ways (each stroke sample to the
inset, each inset point to the strokes, capped at `RIM_FIT_CAP_PX`), and whose corners
lie closest to the strokes' ends (`RIM_FIT_END_WEIGHT`). The ends count most: a side is
drawn from one corner to the next, so where a stroke ends tells t through the
neighbouring side as well as its own (the information the bound of
training/shell_bound.py counts). In pixels, a side seen at a grazing angle weighs less,
as its millimetres are less sure. The strokes must follow
the whole inset at that t (`RIM_OFF_SHARE`), or they are refused as no inset of f's
outline.

A rim drawn about as far in as the solid allows may read a t just past what it takes (the
walls from every face leave no cavity, or offset walls cross): the step is then the
thickest wall under that t that builds, not a refusal.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import cadquery as cq
import numpy as np
from OCP.BRepTools import BRepTools_WireExplorer
from OCP.TopAbs import TopAbs_REVERSED
from scipy.spatial import cKDTree

from ...brep.faces import FaceFrame, face_ref_of
from ...brep.geometry import polyline_length
from ...brep.operators import apply_operation
from ...brep.protocol import OperationError, Shell, WallTooThick
from ...render.camera import OrthoCamera
from ...sketch.curves import CURVE_POINTS, rim_wires
from .common import FitError, is_loop, loop_distances, resample

# Two stroke ends, each the other's nearest, meet (a corner of the rim) within this share
# of the two strokes' mean length: a hand's gap at a corner grows with the sides it
# draws, not with the sketch around them (docs/measurements.md, shell.RIM_JOIN_SHARE).
# A wall line starts within this share of its own length from the rim's ends.
RIM_JOIN_SHARE = 1.0
# A rim sample farther than this (context pixels) from f's outline inset by t is off the
# inset; the strokes are no inset when more than RIM_OFF_SHARE of the rim's samples, or of
# the inset's, are off (see docs/measurements.md, shell.RIM_OFF_PX and RIM_OFF_SHARE).
RIM_OFF_PX = 12.0
RIM_OFF_SHARE = 0.3
# At least this share of the rim's samples, back-projected onto f's plane, lie inside f:
# the rest a hand's spill past a thin wall, which the inset test above then weighs
# (docs/measurements.md, shell.RIM_INSIDE_SHARE)
RIM_INSIDE_SHARE = 0.5
# The pixel fit of t: a distance counts up to RIM_FIT_CAP_PX (a gap an occluder cut, a
# stroke run past a corner; about 4 sigmas of the level-3 hand's ends), t sought from
# RIM_FIT_RANGE times the first t in RIM_FIT_STEPS and as many again between the best
# one's neighbours, the inset's points RIM_FIT_SPACING_PX apart (docs/measurements.md).
RIM_FIT_CAP_PX = 40.0
# How much the strokes' ends, each at its nearest corner of the rim, count against the
# rim's samples (the mean squared gap of either): a side's samples move with its two ends,
# so the ends tell most of t (training/shell_bound.py).
RIM_FIT_END_WEIGHT = 8.0
RIM_FIT_SPACING_PX = 2.0
RIM_FIT_RANGE = (0.4, 1.8)
RIM_FIT_STEPS = 15
# A t the solid cannot take: the thickest that builds is sought down to THINNEST_SHARE of
# it, in BUILD_HALVINGS halvings of the interval (to 1/64 of t: well inside the hand's
# error in t; docs/measurements.md, shell.THINNEST_SHARE)
THINNEST_SHARE = 0.5
BUILD_HALVINGS = 5


@dataclass(frozen=True)
class RimStrokes:
    """A sketch read as a shell's: the indices of the strokes drawing the rim, and of the
    stroke down an inner wall (None when none is drawn)."""

    rim: tuple[int, ...]
    wall: int | None


def rim_and_wall(strokes: list[np.ndarray]) -> RimStrokes:
    """Which strokes draw a closed rim and which one the wall (module docstring).

    Stroke ends are paired at corners (`_corners`); the strokes draw a rim when every
    end finds its partner within RIM_JOIN_SHARE of the two strokes' mean length and the
    pairs chain all strokes into one loop. Failing that, each
    stroke with an end left over is tried as the wall, the others as the rim; the wall
    meets the rim within RIM_JOIN_SHARE of its own length.

    Raises:
        FitError: the strokes do not close into one loop with at most one stroke leaving
            it, saying what they draw instead.
    """
    loops = [i for i, s in enumerate(strokes) if is_loop(s)]
    opened = [i for i in range(len(strokes)) if i not in loops]
    if loops:
        if len(loops) > 1 or len(opened) > 1:
            raise FitError(
                f"a shell's rim is one closed outline; the sketch has {len(loops)} loops "
                f"and {len(opened)} other strokes"
            )
        wall = opened[0] if opened else None
        if wall is not None:
            ends = np.asarray(strokes[wall], float)[[0, -1]]
            reach = RIM_JOIN_SHARE * polyline_length(strokes[wall])
            if loop_distances(ends, np.asarray(strokes[loops[0]], float)).min() > reach:
                raise FitError("a stroke apart from the rim: a shell's sketch is its rim alone")
        return RimStrokes((loops[0],), wall)
    if len(opened) < 3:
        raise FitError("a shell's rim is a closed outline; these strokes do not close")
    left = _corners([strokes[i] for i in opened])
    if not left:
        return RimStrokes(tuple(opened), None)
    for k in sorted({e // 2 for e in left}):
        rest = [i for n, i in enumerate(opened) if n != k]
        if len(rest) >= 3 and not _corners([strokes[i] for i in rest]):
            top = np.asarray(strokes[opened[k]], float)[[0, -1]]
            others = np.concatenate([np.asarray(strokes[i], float)[[0, -1]] for i in rest])
            reach = RIM_JOIN_SHARE * polyline_length(strokes[opened[k]])
            if np.linalg.norm(top[:, None] - others[None], axis=2).min() <= reach:
                return RimStrokes(tuple(rest), opened[k])
    raise FitError(
        f"the strokes do not close into one rim: {len(left)} stroke ends meet no other "
        "(a prism's outline with its depth lines has three at each corner, not a rim)"
    )


def _corners(strokes: list[np.ndarray]) -> list[int]:
    """The ends (2k, 2k + 1: stroke k's first and last) left without a partner when each
    end is paired with the nearest end of another stroke whose nearest end it is too,
    up to RIM_JOIN_SHARE of the two strokes' mean length apart; an empty list only when
    every end has one and the pairs chain the strokes into one loop (else every end, so
    that no loop is read). Mutual, so that a gap as wide as a level-3 hand leaves joins
    its two ends, while three ends meeting at one corner (a prism's depth line at its
    outline) leave one without a partner."""
    ends = np.array([np.asarray(s, float)[[0, -1]] for s in strokes]).reshape(-1, 2)
    gap = np.linalg.norm(ends[:, None] - ends[None], axis=2)
    own = np.arange(len(ends)) // 2
    gap[own[:, None] == own[None]] = np.inf
    length = np.array([polyline_length(s) for s in strokes])[own]
    reach = RIM_JOIN_SHARE * (length[:, None] + length[None]) / 2
    nearest = np.argmin(gap, axis=1)
    mutual = nearest[nearest] == np.arange(len(ends))
    within = gap[np.arange(len(ends)), nearest] <= reach[np.arange(len(ends)), nearest]
    partner = np.where(mutual & within, nearest, -1)
    left = [int(e) for e in np.flatnonzero(partner < 0)]
    if left:
        return left
    seen, end = {0}, 1  # walk the loop from stroke 0's last end
    while (nxt := int(partner[end]) // 2) not in seen:
        seen.add(nxt)
        end = int(partner[end]) ^ 1  # the other end of the stroke reached
    return [] if len(seen) == len(strokes) else list(range(len(ends)))


def _outline_2d(face: cq.Face, frame: FaceFrame) -> list[np.ndarray]:
    """f's outline loops (outer and holes) as closed 2D polylines of f's plane, each edge
    taken in the wire's order and direction (an edge's own parameter may run backwards)."""
    out = []
    for w in [face.outerWire(), *face.innerWires()]:
        pts = []
        walk = BRepTools_WireExplorer(w.wrapped)
        while walk.More():
            e = cq.Edge(walk.Current())
            k = 2 if e.geomType() == "LINE" else CURVE_POINTS
            ts = np.linspace(0, 1, k)[:-1]
            if walk.Orientation() == TopAbs_REVERSED:
                ts = 1 - ts
            pts += [e.positionAt(t).toTuple() for t in ts]
            walk.Next()
        out.append(frame.to_2d(np.array(pts)))
    return out


def _inside(q: np.ndarray, loops: list[np.ndarray]) -> np.ndarray:
    """Whether each 2D point lies inside the region the closed loops bound (even-odd)."""
    inside = np.zeros(len(q), bool)
    for loop in loops:
        a, b = loop, np.roll(loop, -1, axis=0)
        spans = (a[None, :, 1] > q[:, None, 1]) != (b[None, :, 1] > q[:, None, 1])
        dy = np.where(b[:, 1] == a[:, 1], 1e-300, b[:, 1] - a[:, 1])
        x = a[None, :, 0] + (q[:, None, 1] - a[None, :, 1]) * (b - a)[None, :, 0] / dy[None]
        inside ^= (spans & (q[:, None, 0] < x)).sum(axis=1) % 2 == 1
    return inside


def shell_fit(solid: cq.Shape, face: cq.Face, camera: OrthoCamera, rim: list[np.ndarray]) -> Shell:
    """The shell opening planar `face` whose rim the strokes `rim` (pixels of `camera`)
    draw: t where the projected inset outline and the strokes lie closest (module
    docstring).

    Raises:
        FitError: f is not planar, the strokes leave f, or they are no inset of f's outline
            (RIM_OFF_PX, RIM_OFF_SHARE), saying how far off.
    """
    if face.geomType() != "PLANE":
        raise FitError("a shell's rim is drawn on a planar face")
    frame = FaceFrame.of(face)
    pixels = np.concatenate([resample(s) for s in rim])
    on_plane = camera.back_project_to_plane(pixels, frame.origin, frame.normal)
    q = frame.to_2d(on_plane)
    loops = _outline_2d(face, frame)
    dist = np.min([loop_distances(q, loop) for loop in loops], axis=0)
    inside = _inside(q, loops)
    if inside.mean() < RIM_INSIDE_SHARE:
        raise FitError(
            f"the rim leaves the face to open: {100 * (1 - inside.mean()):.0f}% of it lies "
            "outside the face"
        )
    t = float(np.median(dist[inside]))
    if t <= camera.pixel_size:
        raise FitError(
            f"the rim lies on the face's outline (t = {t:.3g} mm, under a pixel): a "
            "shell's walls need a rim drawn inside the face"
        )
    ends = np.array([p for s in rim if not is_loop(s) for p in (s[0], s[-1])], float)
    t = _pixel_fit(face, camera, pixels, ends.reshape(-1, 2), t, _inradius(loops))
    try:
        edges = _inset_edges(face, t)
    except OperationError as e:  # the inset vanishes
        raise FitError(str(e)) from None
    inset = np.concatenate([_edge_points(e, _count(e, camera.pixel_size)) for e in edges])
    inset = camera.project(inset)[0]
    off = float(np.mean(cKDTree(inset).query(pixels)[0] > RIM_OFF_PX))
    missed = float(np.mean(cKDTree(pixels).query(inset)[0] > RIM_OFF_PX))
    if off > RIM_OFF_SHARE or missed > RIM_OFF_SHARE:
        raise FitError(
            f"the strokes are no rim of the face: f's outline inset by t = {t:.3g} mm "
            f"leaves {100 * off:.0f}% of them and {100 * missed:.0f}% of itself more than "
            f"{RIM_OFF_PX:g} px apart (at most {100 * RIM_OFF_SHARE:.0f}%)"
        )
    return Shell(face_ref_of(face), t)


def thickest_that_builds(solid: cq.Solid, face: cq.Face, op: Shell) -> Shell:
    """op where its shell builds on `solid` (opened at `face`, op's f); where t is more
    than the solid takes (`WallTooThick`), the shell of the largest t from
    THINNEST_SHARE of op.t up that builds, to BUILD_HALVINGS halvings.

    Raises:
        OperationError: op's own reason, where it fails otherwise (a solid whose faces no
            offset can follow, OCCT failing) or THINNEST_SHARE of its t does not build
            either.
    """

    def builds(t: float) -> bool:
        try:
            apply_operation(solid, replace(op, t=t), face)
        except OperationError:
            return False
        return True

    try:
        apply_operation(solid, op, face)
        return op
    except WallTooThick:
        low, high = THINNEST_SHARE * op.t, op.t
        if not builds(low):
            raise
    for _ in range(BUILD_HALVINGS):
        mid = (low + high) / 2
        low, high = (mid, high) if builds(mid) else (low, mid)
    return replace(op, t=low)


def _edge_points(edge: cq.Edge, n: int) -> np.ndarray:
    """n 3D points evenly along an edge's parameter (lines and arcs: evenly along it)."""
    if edge.geomType() == "LINE":
        a, b = np.array(edge.startPoint().toTuple()), np.array(edge.endPoint().toTuple())
        return a + np.linspace(0.0, 1.0, n)[:, None] * (b - a)
    us = np.linspace(edge.paramAt(0.0), edge.paramAt(1.0), n)
    return np.array([edge.positionAt(u, "parameter").toTuple() for u in us])


def _count(edge: cq.Edge, spacing: float) -> int:
    """How many points put an edge's about `spacing` apart, its ends included."""
    return 2 + int(edge.Length() / spacing)


def _inset_edges(face: cq.Face, t: float) -> list[cq.Edge]:
    """The edges of f's outline inset by t (`rim_wires`), wire by wire.

    Raises:
        OperationError: the inset vanishes.
    """
    return [e for w in rim_wires(face, t) for e in w.Edges()]


def _inradius(loops: list[np.ndarray], steps: int = 48) -> float:
    """About how thick a wall f's outline allows (the inset vanishes past it): the largest
    distance from the outline of a point inside f, on a grid of `steps` across f."""
    lo, hi = loops[0].min(axis=0), loops[0].max(axis=0)
    u, v = np.meshgrid(*np.linspace(lo, hi, steps).T)
    q = np.column_stack([u.ravel(), v.ravel()])
    q = q[_inside(q, loops)]
    if not len(q):
        return 0.0
    return float(np.min([loop_distances(q, loop) for loop in loops], axis=0).max())


def _pixel_fit(
    face: cq.Face,
    camera: OrthoCamera,
    pixels: np.ndarray,
    ends: np.ndarray,
    t0: float,
    t_max: float,
) -> float:
    """The t around t0, under t_max, whose projected inset lies closest to the stroke
    samples `pixels` both ways and whose corners lie closest to the strokes' `ends`
    (module docstring); t0 where the inset cannot be followed.

    While its edges stay the same, the inset of a planar outline moves linearly in t: the
    points at one parameter of an edge (a corner along its bisector), or for a closed
    edge, whose seam may move, each point along its normal (to the nearest of the edge
    at the other t). So two built insets give it at every t of the range."""
    t1 = 1.05 * t0
    spacing = RIM_FIT_SPACING_PX * camera.pixel_size
    try:
        edges, later = _inset_edges(face, t0), _inset_edges(face, t1)
    except OperationError:
        return t0
    if len(edges) != len(later):
        return t0
    here, moved = [], []
    for e, f in zip(edges, later, strict=True):
        n = _count(e, spacing)
        here.append(_edge_points(e, n))
        if f.IsClosed():  # its seam may have moved: the nearest point
            dense = _edge_points(f, 8 * n)
            moved.append(dense[cKDTree(dense).query(here[-1])[1]])
        else:
            moved.append(_edge_points(f, n))
    start = camera.project(np.concatenate(here))[0]
    rate = (camera.project(np.concatenate(moved))[0] - start) / (t1 - t0)  # px per mm
    strokes = cKDTree(pixels)
    # the corners: each open edge's two ends (a closed edge has none)
    first = np.cumsum([0] + [len(h) for h in here[:-1]])
    corners = [
        i
        for e, a, h in zip(later, first, here, strict=True)
        if not e.IsClosed()
        for i in (a, a + len(h) - 1)
    ]
    tips = ends if corners else ends[:0]

    def cost(t: float) -> float:
        inset = start + (t - t0) * rate
        to_inset = np.minimum(cKDTree(inset).query(pixels)[0], RIM_FIT_CAP_PX)
        to_strokes = np.minimum(strokes.query(inset)[0], RIM_FIT_CAP_PX)
        c = np.mean(to_inset**2) + np.mean(to_strokes**2)
        if len(tips):
            gap = np.linalg.norm(tips[:, None] - inset[corners][None], axis=2).min(axis=1)
            c += RIM_FIT_END_WEIGHT * np.mean(np.minimum(gap, RIM_FIT_CAP_PX) ** 2)
        return float(c)

    # past t_max the inset has vanished (moved on linearly, it would come back mirrored)
    ts = t0 * np.linspace(*RIM_FIT_RANGE, RIM_FIT_STEPS)
    ts = ts[ts < t_max]
    if len(ts) < 3:
        return t0
    k = int(np.argmin([cost(t) for t in ts]))
    ts = np.linspace(ts[max(k - 1, 0)], ts[min(k + 1, len(ts) - 1)], RIM_FIT_STEPS)
    costs = [cost(t) for t in ts]
    k = int(np.argmin(costs))
    if 0 < k < len(ts) - 1:  # the parabola through the least cost and its neighbours
        bend = costs[k - 1] - 2 * costs[k] + costs[k + 1]
        if bend > 0:
            return float(ts[k] + 0.5 * (costs[k - 1] - costs[k + 1]) / bend * (ts[1] - ts[0]))
    return float(ts[k])
