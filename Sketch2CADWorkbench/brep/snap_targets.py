# SPDX-License-Identifier: LGPL-2.1-or-later
"""What a feature on a base face may snap to (key points, edges, earlier features' axes
and sizes), in the face's 2D frame: read by the regularization (inference) and drawn
from by the data generator's regular samples (datagen/regular.py)."""

from __future__ import annotations

from dataclasses import dataclass

import cadquery as cq
import numpy as np

from .faces import CurvedSurface, FaceFrame, is_curved

# Target names that callers pick targets by (the snap messages show every name).
FACE_EDGE = "a face edge"
CENTRE_LINE = "the face's centre line"
ROUND_AXIS = "the axis of an earlier round feature"


@dataclass(frozen=True)
class SnapTargets:
    """What a feature on the base face may snap to, in the face's 2D frame (mm)."""

    points: list[tuple[np.ndarray, str]]  # key points and earlier axes
    lines: list[tuple[np.ndarray, np.ndarray, str]]  # point, unit direction, name
    sizes: list[tuple[float, str]]  # earlier lengths
    radii: list[tuple[float, str]]  # earlier circles' radii
    origin: np.ndarray  # the face's centre: grid origin
    axes: tuple[np.ndarray, ...]  # grid directions: along f's edges
    # (a planar f's two; a curved f's one, along its generatrix)


def _circle(edge: cq.Edge) -> tuple[np.ndarray, np.ndarray, float]:
    """A circular edge's centre, axis and radius."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve

    c = BRepAdaptor_Curve(edge.wrapped).Circle()
    loc, ax = c.Location(), c.Axis().Direction()
    return np.array([loc.X(), loc.Y(), loc.Z()]), np.array([ax.X(), ax.Y(), ax.Z()]), c.Radius()


def _planar_face_targets(face: cq.Face, frame: FaceFrame):
    """A planar f's own targets: its centre, edge midpoints, edges, centre lines and
    corners; the grid runs along its first straight edge and across it."""
    points: list[tuple[np.ndarray, str]] = []
    lines: list[tuple[np.ndarray, np.ndarray, str]] = []
    centre = frame.to_2d(np.array(face.Center().toTuple()))[0]
    points.append((centre, "the face's centre"))
    for e in face.Edges():
        if e.geomType() == "LINE":
            a, b = frame.to_2d(np.array([e.startPoint().toTuple(), e.endPoint().toTuple()]))
            if np.linalg.norm(b - a) > 0:
                d = (b - a) / np.linalg.norm(b - a)
                points.append(((a + b) / 2, "the midpoint of a face edge"))
                lines.append((a, d, FACE_EDGE))
                lines.append((centre, d, CENTRE_LINE))
    points += [
        (p, "a corner of the face")
        for p in frame.to_2d(np.array([v.toTuple() for v in face.Vertices()]))
    ]
    first = next((d for _, d, name in lines if name == FACE_EDGE), np.array([1.0, 0.0]))
    return points, lines, centre, (first, np.array([-first[1], first[0]]))


def _curved_face_targets(face: cq.Face, frame: FaceFrame):
    """A curved f's own targets, in its tangent plane T at p_f (`FaceFrame.tangent`):
    the middle of its height and its rims, where they cross the generatrix through p_f,
    each as a line around the surface; the grid runs along the generatrix only, since
    where around a cylinder a feature stands is the designer's, not a grid's. Its seam,
    and the vertices on it, are no designed edge."""
    surface = CurvedSurface.of(face)
    h_f = float((frame.origin - surface.origin) @ surface.axis)
    radial = frame.origin - surface.origin - h_f * surface.axis
    radial /= np.linalg.norm(radial)

    def on_generatrix(h: float) -> np.ndarray:
        p = surface.origin + h * surface.axis
        return frame.to_2d(p + surface.radius_at(p) * radial)[0]

    heights, rims = [], []
    for e in face.Edges():
        pts = np.array([e.positionAt(t).toTuple() for t in np.linspace(0, 1, 9)])
        h = (pts - surface.origin) @ surface.axis
        heights += [h.min(), h.max()]
        if e.geomType() == "CIRCLE" and np.ptp(h) <= 1e-6 * max(1.0, surface.radius):
            rims.append(float(h.mean()))
    around = np.array([0.0, 1.0])  # T's v, in T's own 2D frame
    centre = on_generatrix(0.5 * (min(heights) + max(heights)))
    lines = [(on_generatrix(h), around, FACE_EDGE) for h in rims]
    lines.append((centre, around, CENTRE_LINE))
    return (
        [(centre, "the middle of the curved face's height")],
        lines,
        centre,
        (np.array([1.0, 0.0]),),
    )


def snap_targets(solid: cq.Shape, face: cq.Face, frame: FaceFrame) -> SnapTargets:
    """The base face's own targets (a planar face's corners, edge midpoints, centre and
    centre lines; a curved face's rims and the middle of its height, in its tangent plane
    `frame`), and the model's circle centres (on axes along n_f), vertices, edges
    parallel to f and sizes, all projected along n_f onto f's plane. The face's own come
    first: they win ties."""
    n = frame.normal
    own = _curved_face_targets if is_curved(face) else _planar_face_targets
    points, lines, centre, axes = own(face, frame)
    sizes, radii = [], []
    for e in solid.Edges():
        kind = e.geomType()
        if kind == "CIRCLE":
            c, axis, r = _circle(e)
            radii.append((r, f"an earlier radius ({r:.4g} mm)"))
            if abs(abs(axis @ n) - 1) < 1e-6:
                points.append((frame.to_2d(c)[0], ROUND_AXIS))
        elif kind == "LINE":  # seams of round faces too: their length is a sweep's d
            length = float(e.Length())
            sizes.append((length, f"an earlier length ({length:.4g} mm)"))
    # vertices and edges of planar faces only: a round face's seam is no designed edge
    for f in solid.Faces():
        if f.geomType() != "PLANE":
            continue
        for e in f.Edges():
            if e.geomType() != "LINE":
                continue
            p, q = np.array(e.startPoint().toTuple()), np.array(e.endPoint().toTuple())
            a, b = frame.to_2d(np.array([p, q]))
            points += [(a, "a vertex of the model"), (b, "a vertex of the model")]
            if abs((q - p) @ n) < 1e-6 * np.linalg.norm(q - p) and np.linalg.norm(b - a) > 0:
                lines.append((a, (b - a) / np.linalg.norm(b - a), "an edge of the model"))
    return SnapTargets(points, lines, sizes, radii, centre, axes)
