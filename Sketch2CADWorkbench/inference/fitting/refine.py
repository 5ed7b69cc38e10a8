# SPDX-License-Identifier: LGPL-2.1-or-later
"""Joint refinement of a fitted prism against all of its strokes (beyond the paper).

The paper fits the start and end N-gons separately, each to its own outline's strokes,
then d by a line search against the far outline. At a grazing view, or with noisy
strokes, one outline of 3-6 short strokes pins the base polygon poorly, while the far
outline and the side edges, which are translates of it, see the same polygon. So the
fitted prism is refined: its base vertices (pixels on f) and d move together until its
3N projected edges and the strokes lie closest to each other, both ways (every stroke
point to the nearest edge, every edge point to the nearest stroke), with a robust
(soft L1) loss so that an overshooting stroke end pulls little. Under orthographic
projection the edges stay straight and the far outline is the base translated by d
times the image of the prism's direction, so the whole refinement runs in 2D.

Closeness alone lets the prism follow each stroke where the hand displaced it; the hand
the data generator models misses a curve's ends by Gaussian noise and spreads that
along the stroke, so the strokes' ends say where the edges' ends are (`verify.end_gaps`).
Both refinements therefore also pull each open curve's ends towards the ends of the
stroke that draws it (`match_ends`), the hand's error model replacing closeness where
the two disagree (REFINE_END_WEIGHT). From the refined prism, `prism_from_ends` then reads it
from the ends alone (closeness, robust loss and all left behind): under that hand the
ends are all a straight stroke tells, and their least squares is the likeliest prism.
The refined prism is kept only where that reading is degenerate (docs/measurements.md,
"Prisms read from their strokes' ends").

A sweep is refined alike (`refine_sweep`): its centre on f, radii and offset d move
together, the profile keeping its fitted shape, until both circles and both profile
lines lie closest to the strokes, both ways. Under orthographic projection every
point of those curves is affine in the parameters, so this runs in 2D too. The paper
fits each circle to its own outline alone (an ellipse with five free parameters, when
the image of a circle about a known axis has three), and a loop or an overshoot at a
hand-drawn ellipse's end pulls it off; the side lines then see the same centre and
radii. The profile keeps its fitted shape: refined with the rest, its control points
follow the noise of short profile strokes. The caller scores the refined sweep beside
the fitted one.

A bevel is refined alike (`refine_bevel`): its profile l's ends slide along the two
edges of f that meet at the corner and its inner control points move in f's plane,
until l and its copy l' at the opposite corner lie closest to both strokes, both ways.
The paper fits l to one stroke back-projected onto f, where a hand's error grows by
1 / cos at a slant; l' is the same curve moved along the crease, so the second stroke
sees it too. The refined l is a reading beside the fitted one, and the one that explains
the strokes better is kept (docs/measurements.md, "Bevel profiles found in the image").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares
from scipy.spatial import cKDTree

from .common import end_order, match_ends, open_ends, resample

ROBUST_PX = 2.0  # residuals beyond about this many pixels count linearly, not squared
EDGE_SAMPLES = 8  # points per prism edge for the edge-to-stroke distances
STROKE_STEP_PX = 3.0  # spacing of the stroke points
MAX_EVALUATIONS = 30  # of the residuals; the fit starts close, so few are needed
# Each end gap's residual is scaled by this times the square root of the stroke points
# per end, so that the ends outweigh closeness: with 3, held-out level-3 add/sub prisms
# and sweeps read closer on average than with 0, 0.3, 1 or 10 (see docs/measurements.md,
# refine.REFINE_END_WEIGHT).
REFINE_END_WEIGHT = 3.0
# The weight (relative to a stroke end's) that holds a vertex no end sees where it was.
HOLD_WEIGHT = 1e-3


def prism_edges(base: np.ndarray, shift: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The 3N image segments of a prism: base outline, far outline, side edges.

    Args:
        base: (N, 2) base polygon, pixels.
        shift: (2,) image displacement from the base to the far outline, pixels.
    Returns:
        (starts, ends), each (3N, 2).
    """
    far = base + shift
    starts = np.concatenate([base, far, base])
    ends = np.concatenate([np.roll(base, -1, axis=0), np.roll(far, -1, axis=0), far])
    return starts, ends


def _layout(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """For the 3N segments of `prism_edges`: the base vertex under each end (ia, ib) and
    whether that end is shifted by d (sa, sb)."""
    i = np.arange(n)
    ia = np.concatenate([i, i, i])
    ib = np.concatenate([(i + 1) % n, (i + 1) % n, i])
    sa = np.concatenate([np.zeros(n), np.ones(n), np.zeros(n)])
    sb = np.concatenate([np.zeros(n), np.ones(n), np.ones(n)])
    return ia, ib, sa, sb


def _unit(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lengths of the rows of v and the rows scaled to unit length (0 where zero)."""
    length = np.linalg.norm(v, axis=-1)
    return length, v / np.maximum(length, 1e-12)[..., None]


def _matched_end_rows(
    x: np.ndarray, step: np.ndarray, ends: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The open strokes' ends matched to the ends of the prism's edges at x (its base
    vertices, pixels, then d; `match_ends`), and what those edge ends are in x: linear,
    so rows @ x gives them, two ends of x and y per matched stroke.

    Returns:
        (r, rows): the matched strokes (indices into `ends`), rows (4 M, 2 N + 1).
    """
    n = (len(x) - 1) // 2
    a, b = prism_edges(x[:-1].reshape(n, 2), x[-1] * step)
    r, c, swapped = match_ends(np.stack([a, b], axis=1), ends)
    which = end_order(swapped)  # (M, 2): a or b
    ia, ib, sa, sb = _layout(n)
    vertex = np.stack([ia, ib], axis=1)[c[:, None], which]  # base vertex
    shifted = np.stack([sa, sb], axis=1)[c[:, None], which]  # moved by d?
    rows = np.zeros((len(r), 2, 2, 2 * n + 1))
    m = np.arange(len(r))
    for k in (0, 1):
        for xy in (0, 1):
            rows[m, k, xy, 2 * vertex[:, k] + xy] = 1.0
        rows[:, k, :, -1] = shifted[:, k, None] * step
    return r, rows.reshape(-1, 2 * n + 1)


def refine_prism(
    base: np.ndarray,
    d: float,
    step: np.ndarray,
    strokes: list[np.ndarray],
    end_weight: float = REFINE_END_WEIGHT,
    every_line: bool = True,
) -> tuple[np.ndarray, float]:
    """Move a prism's base polygon and length together to fit all its strokes.

    Args:
        base: (N, 2) base polygon c on f as fitted, pixels of the context camera.
        d: prism length as fitted, mm (> 0).
        step: (2,) image displacement of 1 mm along the prism's direction (n_f times
            the option's sign), pixels.
        strokes: every stroke of the prism (start, profile, end), pixels.
        end_weight: the strokes' ends' weight (0: closeness alone).
        every_line: the strokes draw every line of the prism, so its lines' distances to
            them count too; False: the base outline is drawn whole and the other lines
            only in part (a drawing without its hidden lines, whose strokes end where a
            line goes out of sight: give no end weight then), so of those only the
            strokes' distances to them count.
    Returns:
        (base, d) refined: the polygon in pixels, the length in mm.
    """
    drawn = np.concatenate([resample(s, STROKE_STEP_PX) for s in strokes])
    tree = cKDTree(drawn)
    n = len(base)
    ia, ib, sa, sb = _layout(n)
    t_edge = np.tile((np.arange(EDGE_SAMPLES) + 0.5) / EDGE_SAMPLES, 3 * n)
    seg_of_sample = np.repeat(np.arange(3 * n), EDGE_SAMPLES)
    # both directions weigh alike whatever the number of points each has
    weight = np.sqrt(len(drawn) / (3 * n * EDGE_SAMPLES)) * (
        (seg_of_sample < n) | every_line  # only the base outline is drawn whole otherwise
    )
    rows_m = np.arange(len(drawn))
    rows_q = len(drawn) + np.arange(len(t_edge))
    ends = open_ends(strokes)
    end_weight = end_weight * np.sqrt(len(drawn) / max(4 * len(ends), 1))

    def evaluate(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        a, b = prism_edges(x[:-1].reshape(n, 2), x[-1] * step)
        # each stroke point to its nearest edge; the distance's gradient moves the
        # edge's two ends in proportion to where the nearest point sits (t)
        ab = b - a
        rel = drawn[:, None, :] - a[None]
        t = np.clip(
            np.einsum("msk,sk->ms", rel, ab) / np.maximum((ab * ab).sum(axis=1), 1e-12), 0.0, 1.0
        )
        gap = a[None] + t[..., None] * ab[None] - drawn[:, None, :]
        j = np.argmin(np.linalg.norm(gap, axis=2), axis=1)
        tm = t[rows_m, j]
        d1, u1 = _unit(gap[rows_m, j])
        # each edge point to its nearest stroke point
        q = a[seg_of_sample] + t_edge[:, None] * ab[seg_of_sample]
        d2, k = tree.query(q)
        _, u2 = _unit(q - drawn[k])
        res = np.concatenate([d1, weight * d2])
        jac = np.zeros((len(res), 2 * n + 1))
        for rows, seg, tt, u in (
            (rows_m, j, tm, u1),
            (rows_q, seg_of_sample, t_edge, weight[:, None] * u2),
        ):
            wa, wb = (1.0 - tt)[:, None] * u, tt[:, None] * u
            for c in (0, 1):  # one (row, column) pair per statement: += is safe
                jac[rows, 2 * ia[seg] + c] += wa[:, c]
                jac[rows, 2 * ib[seg] + c] += wb[:, c]
            jac[rows, -1] = (wa * sa[seg][:, None] + wb * sb[seg][:, None]) @ step
        if end_weight > 0 and len(ends):
            r, rows = _matched_end_rows(x, step, ends)
            res = np.concatenate([res, end_weight * (rows @ x - ends[r].ravel())])
            jac = np.concatenate([jac, end_weight * rows])
        return res, jac

    x0 = np.concatenate([np.asarray(base, float).ravel(), [d]])
    scale = np.concatenate([np.ones(2 * n), [1.0 / max(float(np.linalg.norm(step)), 1e-9)]])
    x = _robust_least_squares(evaluate, x0, x_scale=scale)
    return x[:-1].reshape(n, 2), float(x[-1])


def _robust_least_squares(evaluate, x0: np.ndarray, **options) -> np.ndarray:
    """scipy's least squares with the soft L1 loss from x0, `evaluate(x)` giving the
    residuals and their Jacobian together (computed once for each x); `options` go to
    scipy (bounds, x_scale)."""
    cache: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}

    def cached(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        key = x.tobytes()
        if key not in cache:
            cache.clear()
            cache[key] = evaluate(x)
        return cache[key]

    return least_squares(
        lambda x: cached(x)[0],
        x0,
        jac=lambda x: cached(x)[1],
        loss="soft_l1",
        f_scale=ROBUST_PX,
        max_nfev=MAX_EVALUATIONS,
        ftol=1e-4,
        xtol=1e-4,
        **options,
    ).x


CIRCLE_SAMPLES = 96  # points per circle of a sweep for the distances both ways
PROFILE_SAMPLES = 32  # points per profile line


@dataclass(frozen=True)
class SweepImage:
    """How a sweep's curves move in the image with its parameters (orthographic: affine).

    The parameters x are (a, b, r0, r1, d): the centre's offset (mm) along `side` and
    `other` in f's plane, the radii and the offset. The profile c_p keeps its shape: the
    straight line between the circles plus the fitted `bulge`, its inner control points'
    offsets from that line's thirds, so that in (r, h) it runs at Bezier parameter s
    through ((1 - s) r0 + s r1, s d) + B1(s) bulge[0] + B2(s) bulge[1].

    Attributes:
        origin: (2,) image of the centre as fitted, pixels.
        side, other, axis: (2,) images of 1 mm along the unit vectors the curves are
            drawn with (`sketch.curves.sweep_curves`: `silhouette_side`, axis x side,
            and the sweep's direction).
        bulge: (2, 2) the profile's inner control points minus the straight line's, mm.
    """

    origin: np.ndarray
    side: np.ndarray
    other: np.ndarray
    axis: np.ndarray
    bulge: np.ndarray

    def samples(self) -> tuple[np.ndarray, np.ndarray]:
        """(K, 2, 5) J and (K, 2) c: curve sample k lies at J[k] @ x + c[k] (pixels), for
        both circles and both profile lines."""
        t = np.linspace(0.0, 2 * np.pi, CIRCLE_SAMPLES, endpoint=False)
        ring = np.cos(t)[:, None] * self.side + np.sin(t)[:, None] * self.other  # (T, 2)
        zero = np.zeros_like(ring)
        at = [np.broadcast_to(v, ring.shape) for v in (self.side, self.other)]
        circles = [
            np.stack(at + [ring, zero, zero], axis=2),
            np.stack(at + [zero, ring, np.broadcast_to(self.axis, ring.shape)], axis=2),
        ]
        s = np.linspace(0.0, 1.0, PROFILE_SAMPLES)[:, None]
        bend = 3 * s * (1 - s) ** 2 * self.bulge[0] + 3 * s**2 * (1 - s) * self.bulge[1]
        lines, shifts = [], [np.zeros((2 * CIRCLE_SAMPLES, 2))]
        for sign in (1.0, -1.0):
            at = [np.broadcast_to(v, (len(s), 2)) for v in (self.side, self.other)]
            lines.append(
                np.stack(
                    at + [sign * (1 - s) * self.side, sign * s * self.side, s * self.axis], axis=2
                )
            )
            shifts.append(sign * bend[:, :1] * self.side + bend[:, 1:] * self.axis)
        return np.concatenate(circles + lines), self.origin + np.concatenate(shifts)


def refine_sweep(
    image: SweepImage,
    x: np.ndarray,
    strokes: list[np.ndarray],
    end_weight: float = REFINE_END_WEIGHT,
) -> np.ndarray:
    """Move a sweep's centre, radii and offset together to fit all its strokes, its
    profile keeping its fitted shape (`SweepImage`): refined with the rest, the profile's
    control points followed the noise of short profile strokes.

    Args:
        image: how its curves move with the parameters.
        x: (5,) the parameters as fitted (`SweepImage`; a = b = 0).
        strokes: every stroke of the sweep (circles and profiles), pixels.
        end_weight: the profile strokes' ends' weight (0: closeness alone).
    Returns:
        (5,) the refined parameters (radii and d kept positive).
    """
    x0 = np.asarray(x, float)
    size = max(float(x0[2]), float(x0[3]))
    low = np.array([-np.inf, -np.inf, 1e-3 * size, 1e-3 * size, 1e-3 * x0[4]])
    first = 2 * CIRCLE_SAMPLES + np.array([0, PROFILE_SAMPLES])  # the profile lines' rows
    return _refine_affine(
        *image.samples(),
        np.stack([first, first + PROFILE_SAMPLES - 1], 1),
        strokes,
        np.maximum(x0, low + 1e-9 * size),
        end_weight,
        bounds=(low, np.inf),
    )


def _refine_affine(
    jac_k: np.ndarray,
    const: np.ndarray,
    line_ends: np.ndarray,
    strokes: list[np.ndarray],
    x0: np.ndarray,
    end_weight: float,
    **options,
) -> np.ndarray:
    """The parameters x that bring curves whose samples move affinely with them (sample
    k at jac_k[k] @ x + const[k], pixels) and the strokes closest to each other, both
    ways, with the open curves' ends (`line_ends`: (L, 2) their first and last sample)
    pulled to the ends of the strokes that draw them. `options` go to scipy (bounds)."""
    drawn = np.concatenate([resample(s, STROKE_STEP_PX) for s in strokes])
    tree = cKDTree(drawn)
    n = jac_k.shape[-1]
    weight = np.sqrt(len(drawn) / len(jac_k))
    ends = open_ends(strokes)
    end_weight = end_weight * np.sqrt(len(drawn) / max(4 * len(ends), 1))

    def evaluate(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        q = jac_k @ p + const  # (K, 2) curve samples
        d1, j = cKDTree(q).query(drawn)  # stroke point -> curve
        _, u1 = _unit(q[j] - drawn)
        d2, m = tree.query(q)  # curve -> stroke point
        _, u2 = _unit(q - drawn[m])
        res = np.concatenate([d1, weight * d2])
        jac = np.concatenate(
            [np.einsum("mc,mcp->mp", u1, jac_k[j]), weight * np.einsum("kc,kcp->kp", u2, jac_k)]
        )
        if end_weight > 0 and len(ends):
            r, c, swapped = match_ends(q[line_ends], ends)
            rows = line_ends[c[:, None], end_order(swapped)]  # (M, 2)
            res = np.concatenate([res, end_weight * (q[rows] - ends[r]).ravel()])
            jac = np.concatenate([jac, end_weight * jac_k[rows].reshape(-1, n)])
        return res, jac

    return _robust_least_squares(evaluate, x0, **options)


BEZIER_SAMPLES = 32  # points per bevel profile (l and l') for the distances both ways
EDGE_MARGIN = 0.02  # l's ends stay this share of their edge's length off its ends


@dataclass(frozen=True)
class BevelImage:
    """How a bevel's profile l and its copy l' at the opposite corner move in the image
    with its parameters (orthographic: affine).

    The parameters x are (ta, tb, p1u, p1v, p2u, p2v): where l's two ends lie along the
    two edges of f that meet at the corner c (0 at an edge's first point, 1 at its
    last), and l's inner control points, mm in f's frame (u, v).

    Attributes:
        origin: (2,) image of f's frame origin, pixels.
        to_image: (2, 2) columns: the images of 1 mm along u and v.
        edge_a, edge_b: (2, 2) the two edges' first and last points in f's frame, mm:
            l runs from edge_a to edge_b.
        crease: (2,) image of c' - c: l' is l moved along the crease.
    """

    origin: np.ndarray
    to_image: np.ndarray
    edge_a: np.ndarray
    edge_b: np.ndarray
    crease: np.ndarray

    def control(self, x: np.ndarray) -> np.ndarray:
        """(4, 2) l's control points in f's frame, mm."""
        a0, a1 = self.edge_a
        b0, b1 = self.edge_b
        return np.stack([a0 + x[0] * (a1 - a0), x[2:4], x[4:6], b0 + x[1] * (b1 - b0)])

    def samples(self) -> tuple[np.ndarray, np.ndarray]:
        """(K, 2, 6) J and (K, 2) c: curve sample k lies at J[k] @ x + c[k] (pixels),
        l's BEZIER_SAMPLES first, then l''s."""
        s = np.linspace(0.0, 1.0, BEZIER_SAMPLES)
        b = np.stack([(1 - s) ** 3, 3 * s * (1 - s) ** 2, 3 * s**2 * (1 - s), s**3], 1)
        m = self.to_image
        a0, a1 = self.edge_a
        b0, b1 = self.edge_b
        jac = np.concatenate(
            [
                b[:, :1, None] * (m @ (a1 - a0))[None, :, None],
                b[:, 3:, None] * (m @ (b1 - b0))[None, :, None],
                b[:, 1, None, None] * m[None],
                b[:, 2, None, None] * m[None],
            ],
            axis=2,
        )  # (S, 2, 6)
        const = self.origin + b[:, :1] * (m @ a0) + b[:, 3:] * (m @ b0)
        return np.concatenate([jac, jac]), np.concatenate([const, const + self.crease])


def refine_bevel(
    image: BevelImage,
    x: np.ndarray,
    strokes: list[np.ndarray],
    end_weight: float = REFINE_END_WEIGHT,
) -> np.ndarray:
    """Move a bevel's profile l, its ends sliding along their edges of f, to fit l and
    l' to all the strokes (beyond the paper, which fits l to one stroke: l' draws the
    same curve moved along the crease, so a second stroke sees it too).

    Args:
        image: how l and l' move with the parameters.
        x: (6,) the parameters as fitted (`BevelImage`).
        strokes: every stroke of the bevel, pixels.
        end_weight: the strokes' ends' weight (0: closeness alone).
        every_line: the strokes draw every line of the prism, so its lines' distances to
            them count too; False: the base outline is drawn whole and the other lines
            only in part (a drawing without its hidden lines, whose strokes end where a
            line goes out of sight: give no end weight then), so of those only the
            strokes' distances to them count.
    Returns:
        (6,) the refined parameters (l's ends kept on their edges).
    """
    low = np.array([EDGE_MARGIN, EDGE_MARGIN] + [-np.inf] * 4)
    high = np.array([1 - EDGE_MARGIN, 1 - EDGE_MARGIN] + [np.inf] * 4)
    last = BEZIER_SAMPLES - 1
    # an end's parameter moves it by its edge's length, a control point's by 1 mm
    lengths = [float(np.linalg.norm(e[1] - e[0])) for e in (image.edge_a, image.edge_b)]
    scale = np.array([1.0 / max(v, 1e-9) for v in lengths] + [1.0] * 4)
    return _refine_affine(
        *image.samples(),
        np.array([[0, last], [last + 1, 2 * last + 1]]),
        strokes,
        np.clip(np.asarray(x, float), low, high),
        end_weight,
        bounds=(low, high),
        x_scale=scale,
    )


def prism_from_ends(
    base: np.ndarray, d: float, step: np.ndarray, strokes: list[np.ndarray], rounds: int = 3
) -> tuple[np.ndarray, float]:
    """A prism's base polygon and length read from its open strokes' ends alone.

    Under the hand the generator models, an open stroke's ends are its curve's ends
    moved by Gaussian noise and the rest of it follows them, so the likeliest prism is
    the one whose edges' ends lie closest to the strokes' ends, in least squares. Each
    stroke is paired with the edge whose ends fit its own best (`match_ends`, one to
    one) at the prism as it stands; the ends' images are linear in the base vertices and
    d, so the prism is then solved in closed form, and the pairing renewed `rounds`
    times. A vertex no stroke's end draws keeps its place.

    Args:
        base, d, step, strokes: as `refine_prism`'s, from which this starts.
    Returns:
        (base, d): the polygon in pixels, the length in mm.
    """
    ends = open_ends(strokes)
    n = len(base)
    x = np.concatenate([np.asarray(base, float).ravel(), [d]])
    if not len(ends):
        return base, d
    # a faint pull to where it stands, for vertices (or d) no end sees
    hold = HOLD_WEIGHT * np.diag(np.r_[np.ones(2 * n), np.linalg.norm(step)])
    for _ in range(rounds):
        r, rows = _matched_end_rows(x, step, ends)
        x = np.linalg.lstsq(
            np.concatenate([rows, hold]), np.concatenate([ends[r].ravel(), hold @ x]), rcond=None
        )[0]
    return x[:-1].reshape(n, 2), float(x[-1])
