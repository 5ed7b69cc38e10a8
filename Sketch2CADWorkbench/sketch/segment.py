# SPDX-License-Identifier: LGPL-2.1-or-later
"""Strokes cut and joined into the curves they draw.

    segment_strokes(strokes) -> list[np.ndarray]

People do not draw one stroke per curve: a rectangle goes down in one continuous line,
a long edge in two strokes or traced over, an ellipse in two arcs or left with a gap.
The reader assigns roles and faces per stroke, so before it the strokes become pieces
of curves:

1. cut: each stroke is cut where it turns sharply (a corner: the turn over a short
   window is large and nearly all of it lies in half that window, which a smooth
   curve's turn, however tight, does not);
   A stroke that turns back along itself (a line drawn down and up again, a hook at
   its start) draws the longer leg's line twice: the shorter leg is left out, so the
   piece ends where the pen turned (but for a short line, which a noisy hand folds,
   and an arc run on round a thin ellipse's tip);
2. join: two pieces that continue one another (the second starts near the first one's
   end, or on it, and the pen turns little from one to the other) become one, the
   part drawn twice once; a piece lying along another is absorbed by it; a junction
   where a third piece also ends is a corner of the drawing and is not joined across;
3. close: a piece that turns through most of a loop and whose ends lie apart by a
   gap no hand leaves at the end of a curve is closed by a straight bridge.

Not found: a corner where two curves run on in line in the view (a stroke drawing
both is not cut), and a vertex that a stroke runs through without turning.

Lengths are fractions of the sketch's extent (the diagonal of all the strokes' bounding
box), so the result does not depend on the view's pixel size; nor does it depend on the
order or direction of the strokes. A stroke that nothing applies to comes back as the
same array.
"""

from __future__ import annotations

import numpy as np

from ..brep.geometry import arc_lengths, polyline_length, resample_every

# Half-window (of the extent) over which a stroke's turn is measured: wider than the
# jitter of a hand (real strokes deviate about 1% of a curve's length), narrower than
# a polygon's shortest side.
CORNER_WINDOW = 0.03
# A corner turns more than this over the window (or over twice it)...
CORNER_DEG = 45.0
# ... and at least this share of that turn lies within half the window (a circle's turn
# is spread evenly: half of it; a corner's is concentrated: nearly all of it).
CORNER_SHARPNESS = 0.7
# A turn beyond this is a reversal (the tip of a thin ellipse, drawn without lifting
# the pen), not a corner between two curves.
REVERSAL_DEG = 175.0
# Pieces that continue one another have ends at most this far apart (of the extent; a
# person's split edge leaves a gap of a few percent of it) ...
JOIN_GAP = 0.06
# ... and turn by at most this where they meet (a polygon's corner turns more; two
# arcs of a curve meet at the angle of the window's chords) ...
JOIN_DEG = 30.0
# ... or the second starts within this distance (of the extent) of the first, tracing
# over it; a piece lying within it of another all along is drawn twice.
TRACE_TOL = 0.02
# A loop: it turns through at least this, and its ends lie within this share of its
# length (a person's ellipse left open misses about a tenth of it).
LOOP_TURN_DEG = 270.0
LOOP_GAP = 0.2
# Where another piece ends within this (of the extent), curves meet at a corner of the
# drawing and are not joined there: the ends of a corner drawn with level-1 noise lie
# within 14 px of each other on 256 px (CORNER_REACH in inference/drawing.py).
CORNER_CLEAR = 0.12
# Cut-off bits shorter than this (of the extent) are the pen's hooks, not curves.
MIN_PIECE = 0.02


def sketch_extent(strokes: list[np.ndarray]) -> float:
    """The diagonal of the bounding box of all the strokes' points (at least 1)."""
    pts = np.concatenate([np.asarray(s, float).reshape(-1, 2) for s in strokes])
    return max(float(np.hypot(*np.ptp(pts, axis=0))), 1.0)


def _turn(points: np.ndarray, s: np.ndarray, at: np.ndarray, half: float) -> np.ndarray:
    """The angle (rad) between the chords [at - half, at] and [at, at + half] of a
    polyline with arc lengths s, at arc lengths `at`."""

    def point(t: np.ndarray) -> np.ndarray:
        return np.stack([np.interp(t, s, points[:, k]) for k in range(2)], axis=1)

    here = point(at)
    a, b = here - point(at - half), point(at + half) - here
    cos = (a * b).sum(1) / np.maximum(np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1), 1e-12)
    return np.arccos(np.clip(cos, -1.0, 1.0))


def _window_turns(p: np.ndarray, s: np.ndarray, w: float) -> tuple[np.ndarray, np.ndarray]:
    """Arc lengths every sixth of w, from w to w before the end of a polyline with arc
    lengths s (at least 2 w long), and its turn over the window w at each (`_turn`)."""
    at = np.arange(w, s[-1] - w + w / 12, w / 6)
    return at, _turn(p, s, at, w)


def _is_corner(turn: float, half_turn: float) -> bool:
    """Whether a turn over the window (rad), of which `half_turn` lies within half of
    it, is a corner: not the bend of a smooth curve, nor a reversal."""
    return (
        np.radians(CORNER_DEG) < turn < np.radians(REVERSAL_DEG)
        and half_turn >= CORNER_SHARPNESS * turn
    )


def _spans_at(p: np.ndarray, s: np.ndarray, w: float) -> list[tuple[float, float]]:
    """`corner_spans` measured over one window w."""
    if s[-1] < 2 * w:
        return []
    at, turn = _window_turns(p, s, w)
    over = turn > np.radians(CORNER_DEG)
    spans = []
    k = 0
    while k < len(at):
        if not over[k]:
            k += 1
            continue
        j = k
        while j + 1 < len(at) and over[j + 1]:
            j += 1
        peak = k + int(np.argmax(turn[k : j + 1]))
        # the sharpest half-window turn anywhere in the run: a jump of the pen can move
        # a corner's bend off the peak of the wider turn
        half = float(_turn(p, s, at[k : j + 1], w / 2).max())
        if _is_corner(turn[peak], half):
            spans.append((float(at[k]), float(at[j])))
        k = j + 1
    return spans


def corner_spans(stroke: np.ndarray, extent: float) -> list[tuple[float, float]]:
    """The arc-length spans (start, end) of a stroke's corners, in drawing order.

    Args:
        stroke: (K, 2) polyline.
        extent: the sketch's extent (`sketch_extent`), the unit of the thresholds.
    Returns:
        For each corner, the stretch of arc length around it where the turn over the
        window exceeds CORNER_DEG, over CORNER_WINDOW and over twice that (a corner
        whose turn a short jump of the pen splits in two bends is one corner at the
        wider window); spans less than a window apart are one corner. [] for a smooth
        stroke.
    """
    p = np.asarray(stroke, float)
    if len(p) < 3:
        return []
    s = arc_lengths(p)
    w = CORNER_WINDOW * extent
    found = sorted(_spans_at(p, s, w) + _spans_at(p, s, 2 * w))
    spans: list[tuple[float, float]] = []
    for a, b in found:
        if spans and a - spans[-1][1] < w:
            spans[-1] = (spans[-1][0], max(b, spans[-1][1]))
        else:
            spans.append((a, b))
    return spans


def _between(p: np.ndarray, s: np.ndarray, a: float, b: float) -> np.ndarray:
    """The part of polyline p (arc lengths s) from arc length a to b."""
    inside = (s > a) & (s < b)
    ends = [np.array([np.interp(t, s, p[:, k]) for k in range(2)]) for t in (a, b)]
    return np.vstack([ends[0], p[inside], ends[1]])


def cut_at_corners(stroke: np.ndarray, extent: float) -> list[np.ndarray]:
    """A stroke cut at its corners (`corner_spans`, each span left out), without the
    cut-off bits shorter than MIN_PIECE; [stroke] itself when it has no corner."""
    spans = corner_spans(stroke, extent)
    if not spans:
        return [stroke]
    p = np.asarray(stroke, float)
    s = arc_lengths(p)
    bounds = [0.0] + [t for span in spans for t in span] + [float(s[-1])]
    return [
        _between(p, s, a, b)
        for a, b in zip(bounds[::2], bounds[1::2], strict=False)
        if b - a >= MIN_PIECE * extent
    ]


def _untraced(piece: np.ndarray, extent: float) -> np.ndarray:
    """A piece without the legs it traces back over: at its sharpest turn past
    CORNER_DEG, where the shorter leg lies within TRACE_TOL of the longer on average
    (no loop's tip: a loop is never cut here), the longer runs past a corner's
    neighbourhood (CORNER_CLEAR) and is a line (it turns less than CORNER_DEG: an arc
    run on round a thin ellipse's tip is not), the longer leg alone; again at its next
    such turn. The same array where it has none."""
    w = CORNER_WINDOW * extent
    while len(piece) >= 3 and not is_closed(p := np.asarray(piece, float), extent):
        s = arc_lengths(p)
        if s[-1] < 2 * w:
            break
        at, turn = _window_turns(p, s, w)
        k = int(np.argmax(turn))
        if turn[k] <= np.radians(CORNER_DEG):
            break
        head, tail = _between(p, s, 0.0, at[k]), _between(p, s, at[k], float(s[-1]))
        short, longer = (head, tail) if s[-1] - at[k] > at[k] else (tail, head)
        if polyline_length(longer) <= CORNER_CLEAR * extent:
            break  # a short line folded by the hand's noise, not drawn twice
        if _junction_turn(longer, longer, w) > np.radians(CORNER_DEG):  # start to end
            break  # an arc run on round a thin ellipse's tip: the loop's, not a line's
        if float(distances_to(short, longer).mean()) > TRACE_TOL * extent:
            break
        piece = longer
    return piece


def distances_to(points: np.ndarray, polyline: np.ndarray) -> np.ndarray:
    """Each point's distance (N,) to a polyline (M, 2)."""
    a, b = polyline[:-1], polyline[1:]
    if len(a) == 0:
        return np.linalg.norm(points - polyline[0], axis=1)
    ab = b - a
    t = ((points[:, None] - a[None]) * ab[None]).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-12)
    foot = a[None] + np.clip(t, 0.0, 1.0)[..., None] * ab[None]
    return np.linalg.norm(points[:, None] - foot, axis=-1).min(axis=1)


def total_turn(p: np.ndarray, extent: float) -> float:
    """How far (rad) a polyline's direction turns along it, at the window's scale."""
    q = resample_every(p, CORNER_WINDOW * extent / 2)
    d = np.diff(q, axis=0)
    ang = np.arctan2(d[:, 1], d[:, 0])
    return float(np.abs(np.angle(np.exp(1j * np.diff(ang)))).sum())


def is_closed(p: np.ndarray, extent: float) -> bool:
    """Whether a piece draws a loop (its ends meet, or lie apart by at most LOOP_GAP of
    its length, and it turns through LOOP_TURN_DEG)."""
    gap = float(np.linalg.norm(p[-1] - p[0]))
    return (
        len(p) > 3
        and gap <= LOOP_GAP * polyline_length(p)
        and total_turn(p, extent) >= np.radians(LOOP_TURN_DEG)
    )


def _continuation(
    p: np.ndarray, q: np.ndarray, extent: float, others: np.ndarray
) -> tuple[float, np.ndarray] | None:
    """How q continues p, leaving p's last point with q's first (cost, the joined
    polyline), or None when it does not: q starts within JOIN_GAP of p's end, or on p
    and leaves it near p's end; the joined polyline does not turn at the junction as a
    corner or a reversal does; and no end in `others` (the other pieces' ends) lies at
    the junction (a third curve ending there makes it a corner of the drawing)."""
    tol, reach = TRACE_TOL * extent, JOIN_GAP * extent
    if len(others) and float(np.linalg.norm(others - p[-1], axis=1).min()) <= (
        CORNER_CLEAR * extent
    ):
        return None
    gap = float(np.linalg.norm(q[0] - p[-1]))
    on_p = gap <= tol or float(distances_to(q[:1], p)[0]) <= tol
    if not on_p and gap > reach:
        return None
    cost, tail = gap, q
    if on_p:  # q traces over p's end, then leaves it
        near = distances_to(q, p) <= tol
        leave = int(np.argmin(near))
        if near[leave] or float(np.linalg.norm(q[leave] - p[-1])) > reach + tol:
            return None  # q lies along p all the way (absorbed), or branches off it
        cost, tail = float(near.mean()) * reach, q[leave:]
    joined = np.vstack([p, tail])
    if not is_closed(joined, extent) and _junction_turn(
        p, tail, CORNER_WINDOW * extent
    ) > np.radians(JOIN_DEG):  # (two arcs closing a loop may meet at a thin ellipse's tip)
        return None
    return cost, joined


def _junction_turn(p: np.ndarray, q: np.ndarray, w: float) -> float:
    """The angle (rad) between p's last chord and q's first, each of arc length w (at
    most the piece's): how the pen turns from p to q, whatever the gap between them."""

    def chord(r: np.ndarray) -> np.ndarray:
        s = arc_lengths(r)
        t = min(w, float(s[-1]))
        return np.array([np.interp(t, s, r[:, k]) for k in range(2)]) - r[0]

    a, b = -chord(p[::-1]), chord(q)
    cos = float(a @ b) / max(float(np.linalg.norm(a) * np.linalg.norm(b)), 1e-12)
    return float(np.arccos(np.clip(cos, -1.0, 1.0)))


def _absorbs(p: np.ndarray, q: np.ndarray, extent: float, others: np.ndarray) -> bool:
    """Whether q traces over p: all of q lies within TRACE_TOL of p, q spans more than
    a corner's neighbourhood (CORNER_CLEAR; over a loop, a quarter of it), and q does not end
    at a corner that p runs through (an end in `others`, the other pieces' ends, near
    an end of q and not near one of p: q is another curve seen along p)."""
    tol, clear = TRACE_TOL * extent, CORNER_CLEAR * extent
    if is_closed(p, extent) and not is_closed(q, extent):
        if polyline_length(q) < 0.25 * polyline_length(p):
            return False  # a line touching a loop, not a loop traced over in part
    elif float(np.linalg.norm(q[-1] - q[0])) < clear:
        return False  # an edge at a corner, not a trace
    low, high = p.min(axis=0) - tol, p.max(axis=0) + tol
    if (q.min(axis=0) < low).any() or (q.max(axis=0) > high).any():
        return False
    if not (distances_to(q, p) <= tol).all():
        return False
    for end in (q[0], q[-1]):
        at_corner = len(others) and float(np.linalg.norm(others - end, axis=1).min()) <= clear
        if at_corner and float(np.linalg.norm(p[[0, -1]] - end, axis=1).min()) > clear:
            return False
    return True


def _best_join(
    pieces: list[np.ndarray], closed: list[bool], extent: float
) -> tuple[float, int, int, np.ndarray | None] | None:
    """The cheapest merge of two pieces: (cost, i, j, joined) where joined replaces
    pieces i and j, or None replaces j (absorbed by i)."""
    ends = np.array([[q[0], q[-1]] for q in pieces], float)
    margin = JOIN_GAP * extent
    low = np.array([q.min(axis=0) for q in pieces]) - margin
    high = np.array([q.max(axis=0) for q in pieces]) + margin
    near = np.asarray(((low[:, None] <= high[None]) & (low[None] <= high[:, None])).all(axis=-1))
    lengths = [polyline_length(q) for q in pieces]
    best: tuple[float, int, int, np.ndarray | None] | None = None
    for i, p in enumerate(pieces):
        for j, q in enumerate(pieces):
            if i == j or not near[i, j]:
                continue
            others = np.delete(ends, [i, j], axis=0).reshape(-1, 2)
            if lengths[j] <= lengths[i] and _absorbs(p, q, extent, others):
                cand = (0.0, i, j, None)
                if best is None or cand[:3] < best[:3]:
                    best = cand
                continue
            if closed[i] or closed[j] or j < i:
                continue
            for a in (p, p[::-1]):
                for b in (q, q[::-1]):
                    got = _continuation(a, b, extent, others)
                    if got is not None and (best is None or (got[0], i, j) < best[:3]):
                        best = (got[0], i, j, got[1])
    return best


def segment_strokes(strokes: list[np.ndarray]) -> list[np.ndarray]:
    """The pieces of curves that strokes draw: cut at corners, joined where they
    continue one another or trace over each other, closed where they draw a loop.

    Args:
        strokes: pixel polylines (K, 2), in any order and direction.
    Returns:
        The pieces (K', 2); a stroke that is neither cut, joined nor closed is returned
        as the same array.
    """
    usable = [s for s in strokes if len(s) >= 2]
    if not usable:
        return list(strokes)
    extent = sketch_extent(usable)
    pieces = [_untraced(c, extent) for s in usable for c in cut_at_corners(s, extent)]
    closed = [is_closed(np.asarray(q, float), extent) for q in pieces]
    while len(pieces) > 1:
        best = _best_join([np.asarray(q, float) for q in pieces], closed, extent)
        if best is None:
            break
        _, i, j, joined = best
        if joined is not None:
            pieces[i] = joined
            closed[i] = is_closed(joined, extent)
        del pieces[j], closed[j]
    return [_closed(q, extent) if c else q for q, c in zip(pieces, closed, strict=False)]


def _closed(p: np.ndarray, extent: float) -> np.ndarray:
    """A loop's piece with its ends bridged (unchanged when they lie within JOIN_GAP:
    the hand closed it, as closely as it ends any curve)."""
    if float(np.linalg.norm(p[-1] - p[0])) <= JOIN_GAP * extent:
        return p
    return np.vstack([p, p[:1]])
