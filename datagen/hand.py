# SPDX-License-Identifier: LGPL-2.1-or-later
"""A hand that draws as people do, beside the generator's own (datagen/strokes.py).

The generator's hand draws one whole stroke per curve with Gaussian end noise, every
line included. Real designers' strokes (measured facts in the developers' notes on how
people draw) are smoother but cover their curves in parts, stop short far more often
than they overshoot, draw polygons in one continuous line and leave closed curves
open or close them with a second stroke. This hand draws each sample's curves with
those habits, each with the probability below:

- several curves in one stroke: a chain of curves meeting end to start (a polygon's
  outline, an L or a U shape) is drawn as one stroke of up to MAX_CHAIN curves, with
  probability P_CHAIN per chain;
- one curve in several strokes: split in two with a small gap or overlap (P_SPLIT), or
  traced over by a second, shorter stroke (P_TRACE);
- partial curves: each open end stops short by an exponential share of the length
  (mean SHORT_MEAN) or, with probability P_OVERSHOOT, runs past it; a closed curve is
  left with a gap of 5 to 15% (P_LOOP_OPEN), drawn as two arcs (P_LOOP_ARCS), or
  overdrawn by up to a tenth;
- hidden lines left out: with probability P_HIDDEN_OUT per sample, only what the view
  sees is drawn (generate.view_sample);
- wobble: a low-frequency bow across each stroke (BOW of its length, times the noise
  level) and a light jitter, no end noise beyond the habits above.

Each habit can be drawn alone (`--hand people-HABIT`, HABITS), to tell what each costs
the reader: the others are then off (whole curves, one stroke each, every line, no bow)
while the random draws stay those of `--hand people`, so the sets hold the same
operations in the same views.

Labels: the C~ map is painted per curve (a stroke of several curves paints each with
its own label); a stroke's `stroke_parts` entry is the label of its first curve.
"""

from __future__ import annotations

import numpy as np

from Sketch2CADWorkbench.brep.geometry import arc_lengths, resample_every
from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.sketch.curves import Curve

from .strokes import STEP_PX, StrokeMaps, stroke_maps

# The habits, as the list above names them; "people" draws with all of them.
HABITS = ("chain", "split", "partial", "hidden", "wobble")
HANDS = ("generator", "people", *(f"people-{h}" for h in HABITS))
P_CHAIN = 0.7
MAX_CHAIN = 4
P_SPLIT = 0.3
P_TRACE = 0.15
P_OVERSHOOT = 0.1
SHORT_MEAN = 0.04  # mean shortfall of an end, of the curve's length (real median ~3%)
OVER_MEAN = 0.03
P_LOOP_OPEN = 0.35
P_LOOP_ARCS = 0.3
P_HIDDEN_OUT = 0.5
BOW = 0.01  # RMS bow across a stroke, of its length (real median deviation ~1.25%)
JITTER_PX = 0.3
MEET_PX = 1.5  # clean curve ends this close meet (a polygon's corner)


def _part(p: np.ndarray, a: float, b: float) -> np.ndarray:
    """The part of polyline p from arc-length share a to b (both may leave [0, 1]: the
    ends are extended along the end segments)."""
    q = resample_every(p, STEP_PX)
    s = arc_lengths(q)
    length = max(s[-1], 1e-9)
    t = np.arange(a * length, b * length + STEP_PX / 2, STEP_PX)
    head, tail = q[1] - q[0], q[-1] - q[-2]
    out = np.stack([np.interp(t, s, q[:, k]) for k in range(2)], axis=1)
    before, after = t < 0, t > length
    out[before] = q[0] + t[before, None] * head / max(np.linalg.norm(head), 1e-9)
    out[after] = q[-1] + (t[after, None] - length) * tail / max(np.linalg.norm(tail), 1e-9)
    return out if len(out) >= 2 else q[[0, -1]]


def habits_of(hand: str) -> frozenset[str]:
    """The habits (of HABITS) a hand of HANDS draws with: all for "people", one for
    "people-HABIT", none for the generator's."""
    if hand == "people":
        return frozenset(HABITS)
    return frozenset({hand.removeprefix("people-")} & set(HABITS))


def _end_share(rng: np.random.Generator, partial: bool) -> float:
    """How far an open end of a stroke lies past (+) or short of (-) its curve's end (0
    without the `partial` habit; the draws are the same)."""
    if rng.random() < P_OVERSHOOT:
        share = float(rng.exponential(OVER_MEAN))
    else:
        share = -min(float(rng.exponential(SHORT_MEAN)), 0.3)
    return share if partial else 0.0


def _curve_strokes(
    p: np.ndarray, closed: bool, rng: np.random.Generator, habits: frozenset[str]
) -> list[np.ndarray]:
    """The clean strokes a person draws for one curve (before the wobble)."""
    split, partial = "split" in habits, "partial" in habits
    if closed:
        p = np.roll(p, -int(rng.integers(len(p))), axis=0)
        p = np.vstack([p, p[:1]])
        u = rng.random()
        if u < P_LOOP_OPEN:
            gap = rng.uniform(0.05, 0.15)
            return [_part(p, 0.0, 1.0 - gap if partial else 1.0)]
        if u < P_LOOP_OPEN + P_LOOP_ARCS:
            m = rng.uniform(0.35, 0.65)
            ends = m + rng.normal(0, 0.02), 1.0 + rng.normal(0, 0.02)
            if not split:
                return [_part(p, 0.0, 1.0)]
            return [_part(p, 0.0, ends[0]), _part(p, m, ends[1] if partial else 1.0)]
        over = rng.uniform(0.0, 0.1)
        return [_part(p, 0.0, 1.0 + over if partial else 1.0)]
    a, b = -_end_share(rng, partial), 1.0 + _end_share(rng, partial)
    u = rng.random()
    if u < P_SPLIT:
        m = rng.uniform(0.3, 0.7)
        cuts = m + rng.normal(0, 0.03), m + rng.normal(0, 0.03)
        return [_part(p, a, cuts[0]), _part(p, cuts[1], b)] if split else [_part(p, a, b)]
    if u < P_SPLIT + P_TRACE:
        traced = rng.uniform(0.0, 0.3), rng.uniform(0.7, 1.0)
        return [_part(p, a, b), _part(p, *traced)] if split else [_part(p, a, b)]
    return [_part(p, a, b)]


def _wobble(p: np.ndarray, rng: np.random.Generator, level: int, bow: bool) -> np.ndarray:
    """A stroke with a low-frequency bow across it (when `bow`) and a light jitter."""
    s = arc_lengths(p)
    t = s / max(s[-1], 1e-9)
    d = np.gradient(p, axis=0)
    across = np.stack([-d[:, 1], d[:, 0]], axis=1) / np.maximum(
        np.linalg.norm(d, axis=1, keepdims=True), 1e-9
    )
    sway = rng.normal(0, BOW * level * s[-1]) * np.sin(np.pi * t * rng.uniform(0.7, 1.3))
    return p + across * sway[:, None] * bow + rng.normal(0, JITTER_PX, p.shape)


def _chains(
    ends: np.ndarray, closed: list[bool], rng: np.random.Generator, chain_them: bool
) -> list[list[int]]:
    """Curves grouped into chains drawn as one stroke each, as signed indices (-i-1:
    curve i drawn backwards): a chain runs on through curves whose end meets its own
    (each curve alone without `chain_them`)."""
    free = [i for i in rng.permutation(len(closed)) if not closed[i]]
    out = [[i] for i in range(len(closed)) if closed[i]]
    while free:
        chain = [free.pop(0)]
        if rng.random() < P_CHAIN and chain_them:
            while len(chain) < MAX_CHAIN:
                last = chain[-1]
                tip = ends[last, 1] if last >= 0 else ends[-last - 1, 0]
                nxt = next(
                    (
                        (j, side)
                        for j in free
                        for side in (0, 1)
                        if np.linalg.norm(ends[j, side] - tip) <= MEET_PX
                    ),
                    None,
                )
                if nxt is None:
                    break
                free.remove(nxt[0])
                chain.append(nxt[0] if nxt[1] == 0 else -nxt[0] - 1)
        out.append(chain)
    return out


def people_strokes(
    curves: list[Curve],
    camera: OrthoCamera,
    rng: np.random.Generator,
    noise_level: int,
    habits: frozenset[str] = frozenset(HABITS),
) -> tuple[list[np.ndarray], list[int], StrokeMaps]:
    """Strokes (pixels) of the curves seen by `camera` as a person draws them, in a
    random order and direction, with their labels (each stroke's first curve's) and
    maps (C~ painted per curve).

    Args:
        curves: the sample's curves.
        camera: the view.
        rng: the generator.
        noise_level: 1, 2 or 3: scales the bow.
        habits: those of HABITS drawn ("hidden" is the caller's: it picks the curves).
    """
    pixels = [camera.project(c.points)[0] for c in curves]
    ends = np.array([[p[0], p[-1]] for p in pixels])
    strokes: list[np.ndarray] = []
    labels: list[int] = []
    painted: list[tuple[np.ndarray, int]] = []
    bow = "wobble" in habits
    for chain in _chains(ends, [c.closed for c in curves], rng, "chain" in habits):
        if len(chain) == 1:
            i = chain[0]
            for part in _curve_strokes(pixels[i], curves[i].closed, rng, habits):
                stroke = _wobble(part, rng, noise_level, bow)
                strokes.append(stroke)
                labels.append(int(curves[i].label))
                painted.append((stroke, int(curves[i].label)))
            continue
        pieces = [pixels[i] if i >= 0 else pixels[-i - 1][::-1] for i in chain]
        first = _part(pieces[0], -_end_share(rng, "partial" in habits), 1.0)
        last = _part(pieces[-1], 0.0, 1.0 + _end_share(rng, "partial" in habits))
        runs = [first] + [resample_every(q, STEP_PX) for q in pieces[1:-1]] + [last]
        cuts = np.cumsum([len(r) for r in runs])[:-1]
        stroke = _wobble(np.vstack(runs), rng, noise_level, bow)
        strokes.append(stroke)
        label_of = [int(curves[i if i >= 0 else -i - 1].label) for i in chain]
        labels.append(label_of[0])
        painted += list(zip(np.split(stroke, cuts), label_of, strict=False))
    order = rng.permutation(len(strokes))
    flip = rng.random(len(strokes)) < 0.5
    strokes = [strokes[i][::-1] if flip[i] else strokes[i] for i in order]
    labels = [labels[i] for i in order]
    size = camera.width, camera.height
    maps = stroke_maps([q for q, _ in painted], [v for _, v in painted], *size)
    return strokes, labels, maps


def join_end_to_start(strokes: list[np.ndarray], gap_px: float, most: int = 4) -> list[np.ndarray]:
    """Strokes joined as one continuous line where one starts within `gap_px` of where
    the previous ended: each stroke, in drawing order, runs on into the next one not
    yet used whose start lies that close to its end, up to `most` strokes in one (a
    polygon drawn without lifting the pen)."""
    left = list(range(len(strokes)))
    out = []
    while left:
        chain = [left.pop(0)]
        while len(chain) < most:
            tip = strokes[chain[-1]][-1]
            nxt = next((j for j in left if np.linalg.norm(strokes[j][0] - tip) <= gap_px), None)
            if nxt is None:
                break
            left.remove(nxt)
            chain.append(nxt)
        out.append(np.vstack([strokes[i] for i in chain]))
    return out
