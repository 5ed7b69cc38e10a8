# SPDX-License-Identifier: LGPL-2.1-or-later
"""Stroke roles from geometry, for when the curve map C does not fit (not in the paper).

A prism's or a sweep's profile strokes run along the base face's normal n_f, so in an
orthographic view each is parallel to n_f's image; the outlines at their two ends are
the start outline (lower along n_f) and the end outline. This reads those roles from
the strokes alone, so that a curve map that mixes them up (the networks trained on
this machine's budget often do) need not lose a clear sketch.
"""

from __future__ import annotations

import numpy as np
from matplotlib.path import Path as MplPath
from scipy.spatial import cKDTree

from ...brep.faces import FaceFrame
from ...render.camera import OrthoCamera
from ...sketch.labels import END, PROFILE, START
from .common import FitError, resample
from .polygon import loop_gaps, stroke_loops

# Largest angle (degrees) between a profile stroke's chord and n_f's image: a prism's
# side edges run along n_f; a sweep's profile may flare (a cone, a curved c_p).
PRISM_PROFILE_DEG, SWEEP_PROFILE_DEG = 12.0, 45.0
# ... plus this sideways slack (px) of the chord: a short side edge whose ends moved a
# few pixels (level-1 noise) leans well past 12 degrees. Within 45 degrees in any case.
PROFILE_SLACK_PX = 6.0
# A prism's side-edge strokes share their chord vector within this share of its length
# plus this many pixels (stroke noise). Strict first: an outline side running along n_f's
# image must not join the side edges; then looser, for noisy strokes (level-1 noise
# moves short side edges' ends by several pixels); None: no chord test at all. Each
# tolerance gives one reading; the fitting keeps the one that reprojects best.
SAME_CHORD, SAME_CHORD_PX = 0.15, 3.0
PRISM_CHORD_TOLERANCES = ((SAME_CHORD, SAME_CHORD_PX), (0.35, 10.0), None)
# A stroke whose ends are closer than this share of its length is a closed outline.
CLOSED_SHARE = 0.2
# A closed outline's role is judged on at most this many profiles, those whose middle
# lies nearest its centre (the ends of its own side are near it). It equals the largest
# step interpret() accepts (MAX_STROKES), so every sketch a step accepts is judged on all
# its profiles; only the thousands of strokes of a stress test are bounded, which keeps
# the cost linear in the strokes.
NEAR_PROFILES = 200
# The fewest side edges a prism has: a smaller set of alike chords is no other reading.
MIN_SIDES = 3
# Steps of the search for an outline drawn whole (`whole_outline_roles`) before it gives
# up: a sketch of many strokes meeting near each other has very many chains of them
# (as drawing.COVER_BUDGET bounds the corners' cover; see docs/measurements.md,
# stroke_roles.CYCLE_BUDGET).
CYCLE_BUDGET = 20000
# Below this sine of the angle between n_f and the view, f is seen head-on: profile
# strokes would be dots.
MIN_SIN = 0.1


def normal_image(camera: OrthoCamera, frame: FaceFrame) -> np.ndarray:
    """The unit 2D direction in which +n_f points in the image."""
    v = camera.image_of(frame.normal)
    norm = float(np.linalg.norm(v))
    if norm * camera.pixel_size < MIN_SIN:
        raise FitError("the face is seen head-on, so strokes along its normal cannot be told")
    return v / norm


def _closed(p: np.ndarray) -> bool:
    length = float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())
    return float(np.linalg.norm(p[-1] - p[0])) <= CLOSED_SHARE * max(length, 1e-9)


def _two_circles(strokes: list[np.ndarray], n2: np.ndarray) -> list[int]:
    """A sweep's roles when no profile runs within SWEEP_PROFILE_DEG of n_f (a strongly
    flared cone): two closed strokes are its circles, ordered by their centres along
    n_f's image, and the rest are profiles.

    Raises:
        FitError: not exactly two closed strokes.
    """
    closed = [k for k, s in enumerate(strokes) if _closed(np.asarray(s, float))]
    if len(closed) != 2:
        raise FitError("no stroke runs along the face normal, so no profile was found")
    a, b = closed
    roles = [PROFILE] * len(strokes)
    roles[a], roles[b] = _ordered(strokes, a, b, n2)
    return roles


def _ordered(strokes: list[np.ndarray], a: int, b: int, n2: np.ndarray) -> tuple[int, int]:
    """Roles of closed strokes a and b: the circle whose centre lies lower along n_f's
    image is the start. (Matching the profiles' end points to the circles instead fails
    for a short wide sweep: near the tangent points each circle passes close to both
    ends of a profile.)"""
    ca, cb = (np.mean(resample(np.asarray(strokes[k], float)), axis=0) for k in (a, b))
    return (START, END) if float(ca @ n2) <= float(cb @ n2) else (END, START)


def stroke_roles(
    strokes: list[np.ndarray],
    frame: FaceFrame,
    camera: OrthoCamera,
    prism: bool,
    same_chord: tuple[float, float] | None = (SAME_CHORD, SAME_CHORD_PX),
    sides: int | None = None,
    group: int = 0,
) -> list[int]:
    """Each stroke's role, START (0), PROFILE (1) or END (2), from its shape and place.

    Profile strokes: open strokes whose chord lies within PRISM_PROFILE_DEG (a prism) or
    SWEEP_PROFILE_DEG (a sweep) of n_f's image, give or take PROFILE_SLACK_PX; each is ordered
    by n_f, giving a start point and an end point. A prism's side edges are translates of each
    other, so they must also share one chord vector (within `same_chord`: a share of its length
    and pixels; None skips the test); the largest such set wins, so an outline side that happens
    to run along n_f's image is not taken for a profile. Every other stroke is an outline and
    joins the end of the profiles it touches: an open stroke by its two end points, a closed one
    by passing through all of that end's points (of the NEAR_PROFILES profiles nearest it, when
    there are more: the cost stays linear); of two closed outlines (a sweep's circles), the one
    centred lower along n_f is the start.

    With `sides` (a prism drawn with all its edges has three strokes per side), a
    group of alike chords larger than that keeps the `sides` chords nearest the group's
    median: outline sides that run along n_f's image and happen to match the side
    edges' length within the tolerance would otherwise join the profiles; and when the
    other strokes are 2 * `sides` open ones, the `sides` nearest the profiles' start
    ends are the start outline and the rest the end outline.

    With `group` 1, a prism's profiles are the next largest set of alike chords instead
    (at least MIN_SIDES): where f's outline sides also run along n_f's image (a thin
    slot seen nearly along its length), its long sides and its side edges make two such
    sets, and only the fitting can tell which reading is the step.

    A sweep with no stroke along n_f (a cone flaring past SWEEP_PROFILE_DEG) falls back
    on its two closed strokes (`_two_circles`).

    Raises:
        FitError: f is seen head-on, or no stroke runs along n_f (and, for a sweep,
            there are not exactly two closed strokes), or there is no set `group`.
    """
    n2 = normal_image(camera, frame)
    tan_max = np.tan(np.radians(PRISM_PROFILE_DEG if prism else SWEEP_PROFILE_DEG))
    chords = {}  # stroke index -> (start point, end point), ordered along n_f
    for k, s in enumerate(strokes):
        p = np.asarray(s, float)
        chord = p[-1] - p[0]
        length = float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())
        span = float(np.linalg.norm(chord))
        along, across = abs(float(chord @ n2)), abs(float(chord[0] * n2[1] - chord[1] * n2[0]))
        if (
            span > CLOSED_SHARE * length
            and across < along
            and across <= tan_max * along + PROFILE_SLACK_PX
        ):
            chords[k] = (p[0], p[-1]) if chord @ n2 >= 0 else (p[-1], p[0])
    if prism and chords and same_chord is not None:
        share, px = same_chord
        keys = list(chords)
        vec = np.array([chords[k][1] - chords[k][0] for k in keys])  # (m, 2)
        # the largest group of chords alike (each within share of one's length plus px);
        # a k-d tree counts each chord's neighbours without comparing every pair
        radii = share * np.linalg.norm(vec, axis=1) + px
        tree = cKDTree(vec)
        alike = tree.query_ball_point(vec, radii, return_length=True)
        free = np.ones(len(keys), bool)  # chords in no larger set
        for rank in range(group + 1):
            best = int(np.argmax(np.where(free, alike, -1)))
            kept = np.zeros(len(keys), bool)
            kept[tree.query_ball_point(vec[best], radii[best])] = True
            kept &= free
            free &= ~kept
            if rank and kept.sum() < MIN_SIDES:
                raise FitError(f"no set {rank + 1} of alike strokes along the face normal")
        if sides is not None and kept.sum() > sides:
            gap = np.linalg.norm(vec - np.median(vec[kept], axis=0), axis=1)
            nearest = np.argsort(np.where(kept, gap, np.inf))[:sides]
            kept = np.zeros_like(kept)
            kept[nearest] = True
        chords = {k: chords[k] for k, keep in zip(keys, kept, strict=True) if keep}
    if not chords and not prism:
        return _two_circles(strokes, n2)
    if not chords:
        raise FitError("no stroke runs along the face normal, so no profile was found")
    roles: list[int | None] = [PROFILE if k in chords else None for k in range(len(strokes))]
    starts = np.array([a for a, _ in chords.values()])
    ends = np.array([b for _, b in chords.values()])

    start_tree, end_tree = cKDTree(starts), cKDTree(ends)

    def gap(points: np.ndarray, cloud: cKDTree) -> np.ndarray:
        """Summed distance from each pair of points (..., 2, 2) to the nearest points of
        the cloud."""
        return cloud.query(points)[0].sum(axis=-1)

    others = [k for k in range(len(strokes)) if roles[k] is None]
    closed = [k for k in others if _closed(np.asarray(strokes[k], float))]
    opened = sorted(set(others) - set(closed))
    # an open outline (a prism's side) runs between two ends of its side
    pairs = np.array([np.asarray(strokes[k], float)[[0, -1]] for k in opened]).reshape(-1, 2, 2)
    lean = gap(pairs, end_tree) - gap(pairs, start_tree) if opened else []
    leaning = dict(zip(opened, map(float, lean), strict=True))  # how much nearer the start ends
    if sides is not None and len(leaning) == 2 * sides:
        # all edges drawn: `sides` sides of each outline, the most start-like ones start
        ranked = sorted(leaning, key=lambda k: -leaning[k])
        leaning = {k: (1.0 if i < sides else -1.0) for i, k in enumerate(ranked)}
    for k, lean in leaning.items():
        roles[k] = START if lean >= 0 else END
    if len(closed) == 2:  # a sweep's two circles, ordered by their centres along n_f
        a, b = closed
        roles[a], roles[b] = _ordered(strokes, a, b, n2)
    else:
        for k, near in zip(closed, _near_profiles(strokes, closed, starts, ends), strict=True):
            # a closed outline passes through all the profile ends of its side: a short
            # sweep's two ellipses cross each other, so one nearest point would not do
            q = cKDTree(resample(np.asarray(strokes[k], float)))
            roles[k] = (
                START if q.query(starts[near])[0].sum() <= q.query(ends[near])[0].sum() else END
            )
    return [int(r) for r in roles]


def _near_profiles(
    strokes: list[np.ndarray], closed: list[int], starts: np.ndarray, ends: np.ndarray
) -> list[slice | np.ndarray]:
    """For each closed stroke, the profiles its role is judged on: all of them, in their
    order, when there are at most NEAR_PROFILES; else the NEAR_PROFILES whose middles lie
    nearest the stroke's centre."""
    if len(starts) <= NEAR_PROFILES or not closed:
        return [slice(None)] * len(closed)
    centres = np.array([np.asarray(strokes[k], float).mean(axis=0) for k in closed])
    return list(cKDTree((starts + ends) / 2).query(centres, k=NEAR_PROFILES)[1])


def whole_outline_roles(
    strokes: list[np.ndarray], frame: FaceFrame, camera: OrthoCamera, reach: float
) -> list[int]:
    """A prism's roles when only one outline is drawn whole, as a designer who leaves
    the hidden lines out draws a hole: its rim whole, and of its side edges and floor
    only what the opening shows. The whole outline is the cycle of MIN_SIDES to 6 open
    strokes meeting end to end (within `reach` pixels) that holds the most other
    strokes' middles (a hole's rim holds every other line of it in the image), then
    whose ends meet closest; it is the end outline (a hole's rim
    and a boss's top lie highest along n_f); of the other strokes, those along n_f's image
    (`stroke_roles`' profile test) are side edges, the rest the start outline.

    Raises:
        FitError: f is seen head-on, or no such cycle of strokes.
    """
    n2 = normal_image(camera, frame)
    opened = [k for k, s in enumerate(strokes) if not _closed(np.asarray(s, float))]
    ends = np.array([np.asarray(strokes[k], float)[[0, -1]] for k in opened]).reshape(-1, 2, 2)
    found = []  # strokes, corners, corner gaps
    for path, entered in stroke_loops(ends, reach, (MIN_SIDES, 6), CYCLE_BUDGET):
        corners = np.array([ends[i, e] for i, e in zip(path, entered, strict=True)])
        gaps = float(loop_gaps(ends, path, entered).sum())
        found.append(([opened[i] for i in path], corners, gaps))
    if not found:
        raise FitError("no outline of the prism is drawn whole, its sides meeting end to end")

    resampled = [resample(np.asarray(s, float)) for s in strokes]
    middle = [r[len(r) // 2] for r in resampled]  # once: every cycle asks for them

    def inside(cycle: tuple[list[int], np.ndarray, float]) -> tuple[int, float]:
        """How many other strokes' middles the cycle holds (more first), then its gaps."""
        path, corners, gaps = cycle
        middles = [m for k, m in enumerate(middle) if k not in path]
        held = int(MplPath(corners).contains_points(np.array(middles)).sum()) if middles else 0
        return -held, gaps

    best = min(found, key=inside)[0]
    tan_max = np.tan(np.radians(PRISM_PROFILE_DEG))
    roles = []
    for k, s in enumerate(strokes):
        if k in best:
            roles.append(END)
            continue
        chord = np.asarray(s, float)[-1] - np.asarray(s, float)[0]
        along, across = abs(float(chord @ n2)), abs(float(chord[0] * n2[1] - chord[1] * n2[0]))
        profile = across < along and across <= tan_max * along + PROFILE_SLACK_PX
        roles.append(PROFILE if profile else START)
    return roles
