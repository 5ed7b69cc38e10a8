# SPDX-License-Identifier: LGPL-2.1-or-later
"""Regularization (paper, "Regularization"): rectification and intent-aware snapping.

Rectification keeps the paper's scale-free thresholds: parallelism and equal corner
angles within 20 degrees, equal side lengths where they differ by at most 20% of their
mean (`equalize`, `align_to_edges`, in 2D coordinates of the base face's plane, mm).

Snapping (`regularize_operation`) goes past the paper's "key points within 10% of the
face diameter", which moved a designed off-centre feature on a big face: a fitted value
snaps only to a target that lies within `snap_px` pixels of it in the view the strokes
were drawn in, where the hand's error lives, or within HAND_SNAP times as far as the
strokes miss the reading's own lines, when that is farther (`hand_tolerance`); a target
point up to FIT_REACH times farther is taken when the strokes still fit the feature put
there (the caller's `StrokeCheck`), and a point wins over a line only when about as close
(POINT_OVER_LINE_PX); a long d or radius on the grid moves, as far, onto a round number
(a multiple of ROUND_STEPS) the strokes fit about as well. Targets:
the base face's corners, edge midpoints, centre and centre lines (on a cylinder's or
cone's side: its rims and the middle of its height); earlier features'
circle centres (concentric with a hole or sweep), vertices and straight edges (aligned
with a boss); earlier features' sizes of the same kind (edge lengths for side lengths,
edges along f's normal for a depth, radii for radii); and multiples of the user's grid
step. Every snap applied is returned as a `Snap`, and any of them can be left out
(`skip`) to undo it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import cadquery as cq
import numpy as np

from ...brep.faces import FaceFrame, is_curved
from ...brep.geometry import bezier, unit, vec3
from ...brep.protocol import (
    AddSubPrism,
    Bevel,
    Extrude,
    Operation,
    OperatorType,
    Shell,
    Sweep,
    Vec3,
    per_operator,
    straight_profile,
)
from ...brep.snap_targets import FACE_EDGE, SnapTargets, snap_targets
from ...render.camera import OrthoCamera
from .verify import SketchFit

ANGLE_TOL_DEG = 20.0
LENGTH_TOL = 0.20


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

    Quadrilaterals with corners within 20 degrees of 90 become rectangles, and squares
    when their two side lengths (each the mean of a pair of opposite sides) differ by
    at most LENGTH_TOL of their mean: the paper's "differences of side lengths within
    20% of the average", which a 16 x 22 rectangle, each side within 20% of the mean
    of all four, does not meet (docs/measurements.md, regularize.ANGLE_TOL_DEG,
    LENGTH_TOL).
    Other N-gons become regular when their angles are close and each side lies within
    LENGTH_TOL of their mean: a designer rarely means a hexagon with equal angles and
    unequal sides, and a hand's sides vary more the more it draws. The centre and the
    first side's direction are kept.
    """
    n = len(poly)
    target = (n - 2) * 180.0 / n
    if np.max(np.abs(_angles(poly) - target)) > ANGLE_TOL_DEG:
        return poly
    sides = _sides(poly)
    if n != 4 and np.max(np.abs(sides - sides.mean())) > LENGTH_TOL * sides.mean():
        return poly
    theta = _orientation(poly)
    sign = 1.0 if _ccw(poly) else -1.0
    center = poly.mean(axis=0)
    if n == 4:
        a = (sides[0] + sides[2]) / 2
        b = (sides[1] + sides[3]) / 2
        if abs(a - b) <= LENGTH_TOL * (a + b) / 2:
            a = b = (a + b) / 2
        local = np.array(
            [
                [-a / 2, -sign * b / 2],
                [a / 2, -sign * b / 2],
                [a / 2, sign * b / 2],
                [-a / 2, sign * b / 2],
            ]
        )
    else:
        radius = sides.mean() / (2 * np.sin(np.pi / n))
        # First side along +x, on the side of the centre that keeps the orientation.
        ang = sign * (-np.pi / 2 - np.pi / n + 2 * np.pi * np.arange(n) / n)
        local = radius * np.stack([np.cos(ang), np.sin(ang)], axis=1)
    rot = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])
    return local @ rot.T + center


def align_to_edges(poly: np.ndarray, edge_dirs: np.ndarray) -> np.ndarray:
    """Rotate the polygon about its centre so that its side closest in direction to
    an edge of f (`edge_dirs`: (E, 2) unit directions) becomes parallel to it, when
    within 20 degrees."""
    if len(edge_dirs) == 0:
        return poly
    sides = np.roll(poly, -1, axis=0) - poly
    sang = np.arctan2(sides[:, 1], sides[:, 0])
    eang = np.arctan2(edge_dirs[:, 1], edge_dirs[:, 0])
    diff = (eang[None, :] - sang[:, None] + np.pi / 2) % np.pi - np.pi / 2  # mod 180 deg
    i, j = np.unravel_index(np.argmin(np.abs(diff)), diff.shape)
    delta = float(diff[i, j])
    if abs(np.degrees(delta)) > ANGLE_TOL_DEG:
        return poly
    c = poly.mean(axis=0)
    rot = np.array([[np.cos(delta), -np.sin(delta)], [np.sin(delta), np.cos(delta)]])
    return (poly - c) @ rot.T + c


# ---------------------------------------------------------------- intent-aware snapping

# A value snaps to a target within this many pixels of the view the strokes were drawn
# in (the hand's error): docs/measurements.md, regularize.SNAP_PX.
SNAP_PX = 5.0
# The tolerance grows with the hand: a reading whose own sketch lies m pixels from its
# strokes (its misfit) was drawn by a hand that misses by about that much, so a target
# within HAND_SNAP * m view pixels is taken as meant (docs/measurements.md,
# regularize.HAND_SNAP).
HAND_SNAP = 3.0
# A displacement seen nearly along the view looks short on screen but is not: it counts
# at least this share of its true length in pixels.
FORESHORTEN_FLOOR = 0.5
# A sweep profile whose inner control points stay within this share of d from the
# straight line between its ends is straight (rectified to a cone or cylinder).
STRAIGHT_TOL = 0.08
# A target point (fixing both coordinates) is taken over a target line when it lies at
# most this many view pixels farther from the feature: a point much farther than a line
# is a coincidence the strokes do not draw (mixer session step 2: a block drawn along the
# column's side, 0.5 px from it, jumped 2.85 mm onto the column's corner, 11.5 px away;
# docs/measurements.md, regularize.POINT_OVER_LINE_PX).
POINT_OVER_LINE_PX = SNAP_PX
# A target point beyond the tolerance, up to FIT_REACH times as far, is still taken when
# the strokes fit the feature put there (the caller's `StrokeCheck`: a clear fit): a hand that
# draws a whole outline a few pixels off, seen at a grazing angle, misses by more than its
# lines' wobble says (pipe session step 3: a bore 8 mm off its tube's axis). The nearest
# FIT_TRIES such moves are tried (docs/measurements.md, regularize.FIT_REACH).
FIT_REACH, FIT_TRIES = 3.0, 3
# Designers size long features in round numbers (a 70 mm tube, a 90 mm handle), and a hand
# misjudges where a long outline ends by more than its lines wobble (pipe session: a tube
# read 68.3 for 70, whose low top then misplaces the later steps; hammer: a handle read 92
# for 90). A length read at least ROUND_MIN round steps long (40 mm for 5, 80 for 10: a
# step is at most an eighth of it) moves from the grid onto the nearest multiple of the
# step, coarser first, within FIT_REACH times the tolerance, where the strokes clearly fit
# it (the caller's StrokeCheck) and lie at most ROUND_PX (pixels of the fitting camera)
# farther from its sketch on average than from the grid value's. Shorter lengths keep the
# grid: from 20 mm on, 5 mm steps cost held-out sweeps whose regular lengths are any whole
# mm; and a sloppy hand's strokes, which fit neither clearly, do not choose
# (docs/measurements.md, regularize.ROUND_STEPS).
ROUND_STEPS, ROUND_MIN, ROUND_PX = (10.0, 5.0), 8, 0.3
# Points a bevel's profile and the fillet or chamfer it may snap to are compared at.
ROUND_SAMPLES = 32
# Lines closer in direction than this (|sin| of the angle) are parallel.
PARALLEL_SIN = 0.1
# A free direction slides onto the grid only along a grid direction within 60 degrees of
# it (a planar f's two grid directions always give one within 45).
GRID_ALONG = 0.5

# What a snap changed, as the Sketch panel names it (on a button: at most 14 characters,
# two buttons to a row in FreeCAD's default Tasks panel); also the keys `skip` takes.
SNAP_KINDS = {
    "shape": "shape",
    "align": "direction",
    "size": "side lengths",
    "position": "position",
    "profile": "profile",
    "radii": "radii",
    "r0": "base radius",
    "r1": "far radius",
    "d": "length",
    "t": "wall thickness",
    "rounding": "fillet/chamfer",
    "round_size": "round size",
}


@dataclass(frozen=True)
class Snap:
    """One snap applied to a fitted operation: what moved, to what, from where to where.

    `key` (one of SNAP_KINDS) names the value; `before` and `after` are its values (mm:
    a 2D point in the base face's frame for a position, lengths for sizes).
    """

    key: str
    target: str
    before: tuple[float, ...]
    after: tuple[float, ...]

    def describe(self) -> str:
        """One line for the user; values are shown for points and lengths, not for
        whole outlines (shape, direction, profile)."""

        def fmt(v: tuple[float, ...]) -> str:
            return ", ".join(f"{x:.4g}" for x in v)

        text = f"{SNAP_KINDS[self.key]} snapped to {self.target}"
        if len(self.before) <= 2:
            text += f": ({fmt(self.before)}) -> ({fmt(self.after)}) mm"
        return text


@dataclass(frozen=True)
class StrokeCheck:
    """Whether the strokes fit an operation that snapping moved, as the caller measures.

    `fit(op)`: op's SketchFit to the strokes, in pixels of the camera the reading was
    fitted in (`SketchFit.undrawn()` where op cannot be drawn); within `good_px` of them
    (its misfit_px) they fit it clearly.
    """

    fit: Callable[[Operation], SketchFit]
    good_px: float

    def misfit_px(self, op: Operation) -> float:
        return self.fit(op).misfit_px

    def fits(self, op: Operation) -> bool:
        return self.misfit_px(op) <= self.good_px


@dataclass(frozen=True)
class Regularized:
    """A fitted operation after snapping and rectification, and the snaps applied."""

    operation: Operation
    snaps: tuple[Snap, ...]


class _Snapper:
    """Pixel lengths in the view, and the snaps applied so far."""

    def __init__(
        self,
        frame: FaceFrame,
        view: OrthoCamera,
        tol_px: float,
        step: float,
        skip: frozenset[str],
        strokes: StrokeCheck | None = None,
    ):
        self.frame, self.view, self.tol, self.step, self.skip = frame, view, tol_px, step, skip
        self.strokes = strokes
        self.snaps: list[Snap] = []
        self.depths: list[tuple[float, str]] = []  # what a length along f's normal snaps to

    def px(self, vec3: np.ndarray) -> float:
        """On-screen length (view pixels) of a world displacement (mm)."""
        seen = float(np.linalg.norm(self.view.image_of(vec3)))
        return max(seen, FORESHORTEN_FLOOR * float(np.linalg.norm(vec3)) / self.view.pixel_size)

    def curve_px(self, p: np.ndarray, q: np.ndarray) -> float:
        """How far apart two curves (sampled, (K, 3) world mm) are seen in the view: the
        mean distance (pixels) from each sample to the other curve, both ways."""
        a, b = self.view.project(p)[0], self.view.project(q)[0]
        gaps = np.linalg.norm(a[:, None] - b[None], axis=2)
        return float((gaps.min(axis=1).mean() + gaps.min(axis=0).mean()) / 2)

    def px2(self, vec2: np.ndarray) -> float:
        """On-screen length of a displacement in the face's plane (2D frame, mm)."""
        return self.px(vec2[0] * self.frame.u + vec2[1] * self.frame.v)

    def record(self, key: str, target: str, before, after) -> None:
        self.snaps.append(
            Snap(
                key,
                target,
                tuple(map(float, np.atleast_1d(before))),
                tuple(map(float, np.atleast_1d(after))),
            )
        )

    def length(
        self,
        key: str,
        value: float,
        direction: np.ndarray,
        sizes: list[tuple[float, str]],
        rebuilt: Callable[[float], Operation] | None = None,
    ) -> float:
        """`value` (mm, its sign kept) snapped to the closest earlier size within the
        tolerance, seen as a change along `direction` (3D unit), or else rounded to the
        grid step: the designer chose that resolution, so it applies at any zoom (never
        to 0: a length is at least one step); a grid value then moves onto a round
        number where the strokes fit `rebuilt(length)` about as well (`_round`)."""
        if key in self.skip:
            return value
        mag = abs(value)
        grid = None
        if self.step > 0:
            on_grid = max(self.step, round(mag / self.step) * self.step)
            grid = (abs(on_grid - mag), on_grid, f"the {self.step:g} mm grid")
        best = grid
        for size, name in sizes:
            if (
                size > 0
                and self.px(abs(size - mag) * direction) <= self.tol
                and (best is None or abs(size - mag) < best[0])
            ):
                best = (abs(size - mag), size, name)
        if grid is not None and best is grid and rebuilt is not None:
            best = self._round(mag, grid, direction, rebuilt, float(np.sign(value) or 1.0))
        if best is None or abs(best[1] - mag) <= 1e-9 * max(mag, 1.0):
            return value
        new = float(np.sign(value) * best[1]) if value else best[1]
        self.record(key, best[2], value, new)
        return new

    def _round(
        self,
        mag: float,
        grid: tuple[float, float, str],
        direction: np.ndarray,
        rebuilt: Callable[[float], Operation],
        sign: float,
    ) -> tuple[float, float, str]:
        """The multiple of a round step (ROUND_STEPS, coarsest first, each a multiple of
        the grid step) nearest `mag`, when `mag` is at least ROUND_MIN steps long, the
        multiple lies within FIT_REACH times the tolerance of it, and the strokes fit
        `rebuilt` there clearly and within ROUND_PX of as well as at the `grid` value;
        else `grid`."""
        if self.strokes is None:
            return grid
        at_grid = None
        for q in ROUND_STEPS:
            value = q * round(mag / q)
            if (
                abs(q / self.step - round(q / self.step)) > 1e-9
                or mag < ROUND_MIN * q
                or abs(value - grid[1]) < 1e-9
                or self.px(abs(value - mag) * direction) > FIT_REACH * self.tol
            ):
                continue
            if at_grid is None:
                at_grid = self.strokes.misfit_px(rebuilt(sign * grid[1]))
            at = self.strokes.misfit_px(rebuilt(sign * value))
            if at <= min(self.strokes.good_px, at_grid + ROUND_PX):
                return abs(value - mag), value, f"a round {q:g} mm, where the strokes fit as well"
        return grid

    def position(
        self,
        anchors: np.ndarray,
        targets: SnapTargets,
        moved: Callable[[np.ndarray], Operation] | None = None,
    ) -> np.ndarray:
        """The translation (2D) that puts one of the anchors on the closest target point
        within the tolerance, unless a target line lies much closer (POINT_OVER_LINE_PX);
        failing that, on up to two non-parallel target lines; and,
        with a grid step, the anchors' offsets from the face's centre along its edges
        that no target fixed onto multiples of the step."""
        if "position" in self.skip:
            return np.zeros(2)
        best = None
        for p, name in targets.points:
            for a in anchors:
                px = self.px2(p - a)
                if px <= self.tol and (best is None or px < best[0]):
                    best = (px, p - a, name)
        found = []
        for p, d, name in targets.lines:
            for a in anchors:
                off = (p - a) - ((p - a) @ d) * d
                px = self.px2(off)
                if px <= self.tol:
                    found.append((px, off, p, d, name, a))
        found.sort(key=lambda f: f[0])
        if best is None and not found and moved is not None and self.strokes is not None:
            best = self._fitting_point(anchors, targets, moved)
        if best is not None and (not found or best[0] <= found[0][0] + POINT_OVER_LINE_PX):
            if np.linalg.norm(best[1]) > 1e-9:
                self.record("position", best[2], anchors[0], anchors[0] + best[1])
            return best[1]
        move, names, free = np.zeros(2), [], list(targets.axes)
        if found:
            _, move, _, d1, name, _ = found[0]
            names, free = [name], [d1]
            for _, _, p2, d2, name2, a2 in found[1:]:
                if abs(d1[0] * d2[1] - d1[1] * d2[0]) < PARALLEL_SIN:
                    continue
                n2 = np.array([-d2[1], d2[0]])
                shift = -(n2 @ (a2 + move - p2)) / (n2 @ d1) * d1
                if self.px2(shift) <= self.tol:
                    move, names, free = move + shift, names + [name2], []
                    break
            # two lines meeting on a target point (a face's centre lines) name that point
            names = next(
                (
                    [name]
                    for p, name in targets.points
                    if not free and np.min(np.linalg.norm(anchors + move - p, axis=1)) < 1e-6
                ),
                names,
            )
        if self.step > 0 and free:
            moved = False
            for d in free:  # slide along d until an anchor's offset is on the grid
                g = max(targets.axes, key=lambda g: abs(g @ d))
                if abs(g @ d) < GRID_ALONG:
                    continue  # around a curved f, where no grid runs
                rest = [
                    (self.step * round(t / self.step) - t) / (g @ d) * d
                    for t in ((anchors + move - targets.origin) @ g)
                ]
                shift = min(rest, key=lambda r: float(np.linalg.norm(r)))
                if self.px2(shift) <= self.tol:
                    move, moved = move + shift, moved or np.linalg.norm(shift) > 1e-9
            if moved:
                names.append(f"the {self.step:g} mm grid")
        if names and np.linalg.norm(move) > 1e-9:
            self.record("position", " and ".join(names), anchors[0], anchors[0] + move)
        return move

    def _fitting_point(
        self, anchors: np.ndarray, targets: SnapTargets, moved: Callable[[np.ndarray], Operation]
    ) -> tuple[float, np.ndarray, str] | None:
        """The nearest target point beyond the tolerance (within FIT_REACH times it) that
        the strokes fit the feature moved onto (`moved(move)`), if any."""
        far = []
        for p, name in targets.points:
            for a in anchors:
                px = self.px2(p - a)
                if self.tol < px <= FIT_REACH * self.tol:
                    far.append((px, name, p - a))
        far.sort(key=lambda f: f[0])
        tried: list[np.ndarray] = []
        for px, name, move in far:
            if any(np.linalg.norm(move - t) < 1e-6 for t in tried):
                continue
            if len(tried) == FIT_TRIES:
                break
            tried.append(move)
            if self.strokes.fits(moved(move)):
                return px, move, f"{name}, where the strokes still fit"
        return None


def _is_rectangle(poly: np.ndarray) -> bool:
    return len(poly) == 4 and bool(np.all(np.abs(_angles(poly) - 90.0) < 1e-6))


def _snap_rectangle_sides(poly: np.ndarray, s: _Snapper, sizes) -> np.ndarray:
    """A rectangle's two side lengths snapped (about its centre)."""
    c = poly.mean(axis=0)
    ea, eb = poly[1] - poly[0], poly[2] - poly[1]
    a, b = np.linalg.norm(ea), np.linalg.norm(eb)
    ua, ub = ea / a, eb / b
    if "size" in s.skip:
        return poly
    probe = _Snapper(s.frame, s.view, s.tol, s.step, frozenset())
    na = probe.length("size", a, ua[0] * s.frame.u + ua[1] * s.frame.v, sizes)
    nb = probe.length("size", b, ub[0] * s.frame.u + ub[1] * s.frame.v, sizes)
    if not probe.snaps:
        return poly
    s.record("size", " and ".join(dict.fromkeys(sn.target for sn in probe.snaps)), (a, b), (na, nb))
    local = poly - c
    return c + np.outer(local @ ua * na / a, ua) + np.outer(local @ ub * nb / b, ub)


def _regularize_extrude(op: Extrude, s: _Snapper, targets: SnapTargets) -> Extrude:
    """d snaps to an earlier size or the grid."""
    return replace(op, d=s.length("d", op.d, s.frame.normal, s.depths, lambda d: replace(op, d=d)))


def _regularize_bevel(op: Bevel, s: _Snapper, targets: SnapTargets) -> Bevel:
    """A bevel's corner and crease (or edge) are the solid's own. Its profile l becomes
    a fillet's circular arc tangent to both faces, or a chamfer's straight line, where
    that lies within the tolerance of l in the view (mean distance, view pixels: as
    other shapes snap), the nearer of the two (`regular_candidates`); then the radius,
    or the chamfer's two widths, snap to the grid (`_Snapper.length`). Otherwise l stays
    as drawn."""
    if not op.regular:
        if "rounding" in s.skip:
            return op
        drawn = bezier(np.array(op.profile, float), np.linspace(0, 1, ROUND_SAMPLES))
        off = [
            (s.curve_px(drawn, bezier(np.array(k.profile), np.linspace(0, 1, ROUND_SAMPLES))), k)
            for k in regular_candidates(op)
        ]
        px, new = min(off, key=lambda o: o[0], default=(np.inf, op))
        if px > s.tol:
            return op
        name = FILLET if new.radius is not None else CHAMFER
        s.record("rounding", name, np.ravel(op.profile), np.ravel(new.profile))
        op = new
    c, ctrl = np.asarray(op.corner, float), np.array(op.profile, float)
    ua, ub = (unit(ctrl[k] - c) for k in (0, 3))
    if op.radius is not None:

        def rounded(radius: float) -> Bevel:
            return replace(op, profile=_points(fillet_profile(c, ua, ub, radius)), radius=radius)

        return rounded(s.length("round_size", op.radius, ua, [], rounded))
    widths = [s.length("round_size", w, u, []) for w, u in zip(op.distances, (ua, ub), strict=True)]
    return replace(
        op, profile=_points(chamfer_profile(c, ua, ub, *widths)), distances=(widths[0], widths[1])
    )


def regular_candidates(op: Bevel) -> list[Bevel]:
    """The fillet and the chamfer a freeform bevel's profile l may mean: the circular arc
    tangent to both faces whose ends lie as far from c as l's on average, and the
    straight line between l's ends; none where l's ends are in line with c."""
    c, ctrl = np.asarray(op.corner, float), np.array(op.profile, float)
    ua, ub = (ctrl[k] - c for k in (0, 3))
    a, b = float(np.linalg.norm(ua)), float(np.linalg.norm(ub))
    ua, ub = ua / a, ub / b
    wedge = float(np.arccos(np.clip(ua @ ub, -1.0, 1.0)))  # the angle between the faces
    if not 1e-3 < wedge < np.pi - 1e-3:
        return []
    radius = (a + b) / 2 * np.tan(wedge / 2)
    return [
        replace(op, profile=_points(fillet_profile(c, ua, ub, radius)), radius=float(radius)),
        replace(op, profile=_points(chamfer_profile(c, ua, ub, a, b)), distances=(a, b)),
    ]


def nearest_regular(op: Bevel) -> Bevel:
    """The fillet or chamfer (`regular_candidates`) whose profile lies nearer l (mean
    distance in 3D): what a bevel along a chain or an outline, which OCCT builds only as
    one of them, reads its profile as; `op` itself where l has neither."""
    drawn = bezier(np.array(op.profile, float), np.linspace(0, 1, ROUND_SAMPLES))

    def gap(k: Bevel) -> float:
        other = bezier(np.array(k.profile, float), np.linspace(0, 1, ROUND_SAMPLES))
        return float(np.linalg.norm(drawn[:, None] - other[None], axis=2).min(axis=1).mean())

    return min(regular_candidates(op), key=gap, default=op)


FILLET, CHAMFER = "a fillet (a circular arc)", "a chamfer (a straight line)"


def fillet_profile(c: np.ndarray, ua: np.ndarray, ub: np.ndarray, radius: float) -> np.ndarray:
    """The cubic Bezier (4, 3) of the arc of `radius` tangent to the lines c + s ua and
    c + s ub (unit directions), from the first to the second."""
    wedge = float(np.arccos(np.clip(ua @ ub, -1.0, 1.0)))
    reach = radius / np.tan(wedge / 2)  # from c to where the arc touches each line
    handle = 4 / 3 * np.tan((np.pi - wedge) / 4) * radius
    p0, p3 = c + reach * ua, c + reach * ub
    return np.stack([p0, p0 - handle * ua, p3 - handle * ub, p3])


def chamfer_profile(
    c: np.ndarray, ua: np.ndarray, ub: np.ndarray, a: float, b: float
) -> np.ndarray:
    """The straight line (4, 3) from c + a ua to c + b ub, its inner points at thirds."""
    p0, p3 = c + a * ua, c + b * ub
    return np.stack([p0, p0 + (p3 - p0) / 3, p0 + 2 * (p3 - p0) / 3, p3])


def _points(ctrl: np.ndarray) -> tuple[Vec3, Vec3, Vec3, Vec3]:
    p0, p1, p2, p3 = (vec3(p) for p in ctrl)
    return (p0, p1, p2, p3)


def _regularize_shell(op: Shell, s: _Snapper, targets: SnapTargets) -> Shell:
    """t, measured across the rim in f's plane, rounds to the grid or a round length."""
    return replace(op, t=s.length("t", op.t, s.frame.u, [], lambda t: replace(op, t=t)))


def _regularize_prism(op: AddSubPrism, s: _Snapper, targets: SnapTargets) -> AddSubPrism:
    """Rectify the base polygon and align it with f's edges (the paper's angle and length
    thresholds), snap a rectangle's sides, then its position, then d."""
    frame = s.frame
    poly = frame.to_2d(np.array(op.polygon, float))
    edge_dirs = np.array([d for _, d, nm in targets.lines if nm == FACE_EDGE]).reshape(-1, 2)
    for key, rectify in (("shape", equalize), ("align", lambda p: align_to_edges(p, edge_dirs))):
        if key not in s.skip:
            new = rectify(poly)
            if np.max(np.linalg.norm(new - poly, axis=1)) > 1e-9:
                s.record(
                    key,
                    {"shape": "equal angles and sides", "align": "a face edge's direction"}[key],
                    poly.ravel(),
                    new.ravel(),
                )
                poly = new
    if _is_rectangle(poly):
        poly = _snap_rectangle_sides(poly, s, targets.sizes)
    mids = (poly + np.roll(poly, -1, axis=0)) / 2

    def moved(move: np.ndarray) -> AddSubPrism:
        return replace(op, polygon=tuple(tuple(map(float, p)) for p in frame.to_3d(poly + move)))

    move = s.position(np.concatenate([poly.mean(axis=0)[None], poly, mids]), targets, moved)
    op = moved(move)
    return replace(op, d=s.length("d", op.d, frame.normal, s.depths, lambda d: replace(op, d=d)))


def best_line(op: Sweep) -> tuple[float, float]:
    """The radii at both ends of the straight line r = a + b h that fits the sweep's
    profile c_p best (least squares over c_p sampled evenly in h from 0 to d)."""
    t = np.linspace(0.0, 1.0, 65)
    rh = bezier(np.array(op.control_points(), float), t)
    weight = np.abs(np.gradient(rh[:, 1], t))  # evenly in h, however c_p runs in t
    if weight.sum() <= 0:
        return op.r0, op.r1
    a, b = np.polyfit(rh[:, 1], rh[:, 0], 1, w=np.sqrt(weight))[::-1]
    return float(a), float(a + b * op.d)


def _regularize_sweep(op: Sweep, s: _Snapper, targets: SnapTargets) -> Sweep:
    """A nearly straight profile becomes the cone that fits it best (`best_line`: a
    profile fitted with a bulge its strokes did not have, and end radii that make up for
    it, becomes the cone its sides draw), a cylinder when the radii are within 20% and
    the tolerance; then c0's centre, the radii and d snap."""
    frame, n = s.frame, s.frame.normal
    r0, r1, d = op.r0, op.r1, op.d
    mid = np.array(op.profile, float)
    # how far the inner control points lie from the line, not from its thirds: points
    # slid along the line (a hand drawing the side faster at one end) keep it straight
    along = np.array([r1 - r0, d]) / np.hypot(r1 - r0, d)
    off = mid - (r0, 0.0)
    straight = np.max(np.abs(off[:, 0] * along[1] - off[:, 1] * along[0])) <= STRAIGHT_TOL * d
    if straight and "profile" not in s.skip:
        line = best_line(op)
        chord = np.array(straight_profile(*line, d))
        if (
            min(line) > 0
            and np.max(np.abs(np.r_[mid.ravel(), r0, r1] - np.r_[chord.ravel(), line])) > 1e-9
        ):
            s.record(
                "profile",
                "a straight line (a cone)",
                (r0, r1, *mid.ravel()),
                (*line, *chord.ravel()),
            )
            r0, r1 = line
            op = replace(op, r0=r0, r1=r1, profile=tuple(tuple(map(float, p)) for p in chord))
    radial = frame.u  # radii change the rim's size in f's plane
    if (
        straight
        and "radii" not in s.skip
        and 0 < abs(r0 - r1) <= LENGTH_TOL * (r0 + r1) / 2
        and s.px(abs(r0 - r1) / 2 * radial) <= s.tol
    ):
        r = (r0 + r1) / 2
        s.record("radii", "each other (a cylinder)", (r0, r1), (r, r))
        op = op.retuned(r, r)
    c = frame.to_2d(np.array(op.center, float))[0]
    c = c + s.position(
        c[None],
        targets,
        lambda move: replace(op, center=tuple(map(float, frame.to_3d(c + move)[0]))),
    )
    op = replace(op, center=tuple(map(float, frame.to_3d(c)[0])))
    if op.r0 == op.r1:
        r = s.length("r0", op.r0, radial, targets.radii, lambda r: op.retuned(r, r))
        op = op.retuned(r, r)
    else:
        r0 = s.length("r0", op.r0, radial, targets.radii, lambda r: op.retuned(r0=r))
        op = op.retuned(
            r0, s.length("r1", op.r1, radial, targets.radii, lambda r: op.retuned(r0, r))
        )
    return op.retuned(d=s.length("d", op.d, n, s.depths, lambda d: op.retuned(d=d)))


_REGULARIZE = per_operator(
    {
        OperatorType.EXTRUDE: _regularize_extrude,
        OperatorType.BEVEL: _regularize_bevel,
        OperatorType.ADDSUB: _regularize_prism,
        OperatorType.SWEEP: _regularize_sweep,
        OperatorType.SHELL: _regularize_shell,
    },
    "_REGULARIZE",
)


def hand_tolerance(
    snap_px: float, misfit_px: float, context: OrthoCamera, view: OrthoCamera
) -> float:
    """The snapping tolerance (view pixels) for a reading: `snap_px`, or HAND_SNAP times
    its misfit when larger.

    Args:
        snap_px: the designer's tolerance, view pixels.
        misfit_px: the reading's symmetric mean distance to the strokes, in pixels of
            `context` (the camera it was fitted in, framed on the strokes).
        view: the camera the strokes were drawn in.
    """
    return max(snap_px, HAND_SNAP * misfit_px * context.pixel_size / view.pixel_size)


def _depths(solid: cq.Shape, normal: np.ndarray) -> list[tuple[float, str]]:
    """The earlier lengths a length along `normal` (a depth) may snap to: the straight
    edges along it (earlier depths and heights measured the same way, seams of round
    faces included), not the sizes across it (a boss's width is no depth)."""
    out = []
    for e in solid.Edges():
        if e.geomType() == "LINE":
            d = np.subtract(e.endPoint().toTuple(), e.startPoint().toTuple())
            size = float(np.linalg.norm(d))
            if size > 0 and np.linalg.norm(np.cross(d / size, normal)) < PARALLEL_SIN:
                out.append((size, f"an earlier depth ({size:.4g} mm)"))
    return out


def regularize_operation(
    solid: cq.Shape,
    op: Operation,
    face: cq.Face,
    view: OrthoCamera,
    step: float = 0.0,
    tol_px: float = SNAP_PX,
    skip: frozenset[str] = frozenset(),
    strokes: StrokeCheck | None = None,
) -> Regularized:
    """Rectify a fitted operation and snap it to what its strokes are close to.

    Args:
        solid: the model the operation applies to (earlier features' axes, edges, sizes).
        op: the fitted operation; `face` its base face f: on a curved f the frame is
            the tangent plane T at op.face's p_f, where its polygon or c0 lies.
        view: the camera the strokes were drawn in: tolerances are its pixels.
        step: the grid step for lengths, mm (0: no grid).
        tol_px: the snapping tolerance, view pixels.
        skip: SNAP_KINDS keys not to apply (a snap the designer undid).
        strokes: how well the strokes fit an operation snapping moved: a target point
            beyond the tolerance is taken when they fit the feature put there (FIT_REACH),
            a round length when they fit it about as well (ROUND_PX).
    Returns:
        The operation and the snaps applied, in order.
    """
    frame = FaceFrame.tangent(face, op.face) if is_curved(face) else FaceFrame.of(face)
    s = _Snapper(frame, view, tol_px, step, frozenset(skip), strokes)
    s.depths = _depths(solid, frame.normal)
    op = _REGULARIZE[op.type](op, s, snap_targets(solid, face, frame))
    return Regularized(op, tuple(s.snaps))
