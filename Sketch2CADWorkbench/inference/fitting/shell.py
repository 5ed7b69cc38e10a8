# SPDX-License-Identifier: LGPL-2.1-or-later
"""Shell (beyond the paper): the wall thickness t read from the rim drawn on the face to
open.

The designer draws, on the face f to open, the inner rim the walls leave: f's outline
inset by t, as one loop or one stroke per side (a loop is cut at its corners before it
gets here: sketch/segment.py). A stroke down an inner wall from a corner of the rim may
follow; it says nothing more and is set aside.

    rim_and_wall(strokes) -> RimStrokes       which strokes draw the rim, which the wall
    shell_fit(solid, face, camera, rim) -> Shell

The strokes are a rim when they close into one loop: their ends, paired at the corners
closest first, chain every stroke into it, but for one stroke with a free end whose
other end meets a corner (the wall). A prism's outline with its depth lines has three
strokes at each corner, so ends are left over and it is not read as a rim.

t is where the rim lies: each of its samples, back-projected onto f's plane, lies t from
f's outline, and t is their median (robust to the hand's wobble). The rim must follow
the whole outline at that one distance (`RIM_OFF_SHARE`), or the strokes are refused as
no inset of f's outline.
"""

from __future__ import annotations

from dataclasses import dataclass

import cadquery as cq
import numpy as np
from OCP.BRepTools import BRepTools_WireExplorer
from OCP.TopAbs import TopAbs_REVERSED

from ...brep.faces import FaceFrame, face_ref_of
from ...brep.protocol import OperationError, Shell
from ...render.camera import OrthoCamera
from ...sketch.curves import CURVE_POINTS, rim_wires
from .common import FitError, is_loop, loop_distances, resample

# Two stroke ends within this share of the sketch's extent meet (a corner of the rim), as
# a corner of the drawing is found in sketch/segment.py: level-1 hands left gaps up to
# 0.099 of the extent at a rim's corners (docs/measurements.md, shell.RIM_JOIN_SHARE).
RIM_JOIN_SHARE = 0.12
# A rim sample farther than this (context pixels) from f's outline inset by t is off the
# inset; the strokes are no inset when more than RIM_OFF_SHARE of the rim's samples, or of
# the inset's, are off (see docs/measurements.md, shell.RIM_OFF_PX and RIM_OFF_SHARE).
RIM_OFF_PX = 6.0
RIM_OFF_SHARE = 0.3


@dataclass(frozen=True)
class RimStrokes:
    """A sketch read as a shell's: the indices of the strokes drawing the rim, and of the
    stroke down an inner wall (None when none is drawn)."""

    rim: tuple[int, ...]
    wall: int | None


def rim_and_wall(strokes: list[np.ndarray]) -> RimStrokes:
    """Which strokes draw a closed rim and which one the wall (module docstring).

    Stroke ends are paired at corners, the closest two first (`_corners`); the strokes
    draw a rim when every end finds its partner within RIM_JOIN_SHARE of the sketch's
    extent and the pairs chain all strokes into one loop. Failing that, each stroke with
    an end left over is tried as the wall, the others as the rim.

    Raises:
        FitError: the strokes do not close into one loop with at most one stroke leaving
            it, saying what they draw instead.
    """
    loops = [i for i, s in enumerate(strokes) if is_loop(s)]
    opened = [i for i in range(len(strokes)) if i not in loops]
    pts = np.concatenate([np.asarray(s, float) for s in strokes])
    join = RIM_JOIN_SHARE * float(np.ptp(pts, axis=0).max())
    if loops:
        if len(loops) > 1 or len(opened) > 1:
            raise FitError(
                f"a shell's rim is one closed outline; the sketch has {len(loops)} loops "
                f"and {len(opened)} other strokes"
            )
        wall = opened[0] if opened else None
        if wall is not None:
            ends = np.asarray(strokes[wall], float)[[0, -1]]
            if loop_distances(ends, np.asarray(strokes[loops[0]], float)).min() > join:
                raise FitError("a stroke apart from the rim: a shell's sketch is its rim alone")
        return RimStrokes((loops[0],), wall)
    if len(opened) < 3:
        raise FitError("a shell's rim is a closed outline; these strokes do not close")
    left = _corners([strokes[i] for i in opened], join)
    if not left:
        return RimStrokes(tuple(opened), None)
    for k in sorted({e // 2 for e in left}):
        rest = [i for n, i in enumerate(opened) if n != k]
        if len(rest) >= 3 and not _corners([strokes[i] for i in rest], join):
            top = np.asarray(strokes[opened[k]], float)[[0, -1]]
            others = np.concatenate([np.asarray(strokes[i], float)[[0, -1]] for i in rest])
            if np.linalg.norm(top[:, None] - others[None], axis=2).min() <= join:
                return RimStrokes(tuple(rest), opened[k])
    raise FitError(
        f"the strokes do not close into one rim: {len(left)} stroke ends meet no other "
        "(a prism's outline with its depth lines has three at each corner, not a rim)"
    )


def _corners(strokes: list[np.ndarray], join: float) -> list[int]:
    """The ends (2k, 2k + 1: stroke k's first and last) left without a partner when the
    closest two ends of different strokes are paired first, up to `join` apart; an empty
    list only when every end has one and the pairs chain the strokes into one loop (else
    every end, so that no loop is read)."""
    ends = np.array([np.asarray(s, float)[[0, -1]] for s in strokes]).reshape(-1, 2)
    gap = np.linalg.norm(ends[:, None] - ends[None], axis=2)
    own = np.arange(len(ends)) // 2
    gap[own[:, None] == own[None]] = np.inf
    partner = np.full(len(ends), -1)
    for flat in np.argsort(gap, axis=None):
        a, b = divmod(int(flat), len(ends))
        if gap[a, b] > join:
            break
        if partner[a] < 0 and partner[b] < 0:
            partner[a], partner[b] = b, a
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
    draw: t the median distance of their samples, on f's plane, from f's outline.

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
    if inside.mean() < 1 - RIM_OFF_SHARE:
        raise FitError(
            f"the rim leaves the face to open: {100 * (1 - inside.mean()):.0f}% of it lies "
            "outside the face"
        )
    t = float(np.median(dist[inside]))
    tol = RIM_OFF_PX * camera.pixel_size
    if t <= camera.pixel_size:
        raise FitError(
            f"the rim lies on the face's outline (t = {t:.3g} mm, under a pixel): a "
            "shell's walls need a rim drawn inside the face"
        )
    op = Shell(face_ref_of(face), t)
    off = float(np.mean(np.abs(dist - t) > tol))
    try:
        wires = rim_wires(face, t)
    except OperationError as e:  # the inset vanishes
        raise FitError(str(e)) from None
    inset = np.concatenate(
        [
            frame.to_2d(np.array([e.positionAt(s).toTuple() for s in np.linspace(0, 1, 64)]))
            for w in wires
            for e in w.Edges()
        ]
    )
    missed = float(np.mean(np.linalg.norm(inset[:, None] - q[None], axis=2).min(axis=1) > tol))
    if off > RIM_OFF_SHARE or missed > RIM_OFF_SHARE:
        raise FitError(
            f"the strokes are no rim of the face: f's outline inset by t = {t:.3g} mm "
            f"leaves {100 * off:.0f}% of them and {100 * missed:.0f}% of itself more than "
            f"{RIM_OFF_PX:g} px apart (at most {100 * RIM_OFF_SHARE:.0f}%)"
        )
    return op
