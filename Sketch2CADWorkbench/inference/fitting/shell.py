# SPDX-License-Identifier: LGPL-2.1-or-later
"""Shell (beyond the paper): the wall thickness t read from the rim drawn on the face to
open.

The designer draws, on the face f to open, the inner rim the walls leave: f's outline
inset by t, as one loop or one stroke per side (a loop is cut at its corners before it
gets here: sketch/segment.py). A stroke down an inner wall from a corner of the rim may
follow; it says nothing more and is set aside.

    rim_and_wall(strokes) -> RimStrokes       which strokes draw the rim, which the wall
    shell_fit(solid, face, camera, rim) -> Shell

The strokes are a rim when they close into one loop: every end of a stroke meets the end
of exactly one other stroke (a corner of the rim), but for one stroke with a free end
whose other end meets a corner (the wall). A prism's outline with its depth lines has
three strokes at each corner, so it is never read as a rim.

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

# Two stroke ends within this share of the sketch's extent meet (a corner of the rim):
# the hand's gaps at a corner (datagen/strokes.py) stay under a tenth of the extent (see
# docs/measurements.md, shell.RIM_JOIN_SHARE).
RIM_JOIN_SHARE = 0.08
# A rim sample farther than this (context pixels) from f's outline inset by t is off the
# inset; the strokes are no inset when more than RIM_OFF_SHARE of the rim's samples, or of
# the inset's, are off (see docs/measurements.md, shell.RIM_OFF_PX and RIM_OFF_SHARE).
RIM_OFF_PX = 6.0
RIM_OFF_SHARE = 0.2


@dataclass(frozen=True)
class RimStrokes:
    """A sketch read as a shell's: the indices of the strokes drawing the rim, and of the
    stroke down an inner wall (None when none is drawn)."""

    rim: tuple[int, ...]
    wall: int | None


def rim_and_wall(strokes: list[np.ndarray]) -> RimStrokes:
    """Which strokes draw a closed rim and which one the wall (module docstring).

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
    ends = np.array([np.asarray(strokes[i], float)[[0, -1]] for i in opened]).reshape(-1, 2)
    near = np.linalg.norm(ends[:, None] - ends[None], axis=2) <= join
    near[np.arange(len(ends)), np.arange(len(ends))] = False
    own = np.arange(len(ends)) // 2
    near[own[:, None] == own[None]] = False  # a side's two ends are not a corner
    degree = near.sum(axis=1)
    free = np.flatnonzero(degree == 0)
    crowded = np.flatnonzero(degree >= 3)
    walls = [int(own[k]) for k in free]
    # without a wall every end meets one other; a wall's top meets a corner's two ends
    if len(free) > 1 or len(crowded) or (degree == 2).sum() > (3 if len(free) else 0):
        raise FitError(
            "the strokes do not close into one rim: "
            f"{len(free)} free ends and {(degree >= 2).sum()} ends where three strokes meet "
            "(a prism's outline with its depth lines, not a rim)"
        )
    if walls and degree[own == walls[0]].max() != 2:
        raise FitError("the stroke leaving the rim does not start at a corner of it")
    rim = tuple(opened[k] for k in range(len(opened)) if k not in walls)
    if len(rim) < 3:
        raise FitError("a shell's rim is a closed outline; these strokes do not close")
    return RimStrokes(rim, opened[walls[0]] if walls else None)


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
    if t <= tol:
        raise FitError(
            f"the rim lies on the face's outline (t = {t:.3g} mm, under the hand's "
            f"{tol:.3g} mm): a shell's walls need a rim drawn inside the face"
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
