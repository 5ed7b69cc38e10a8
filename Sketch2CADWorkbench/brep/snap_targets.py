# SPDX-License-Identifier: LGPL-2.1-or-later
"""What a feature on a planar face may snap to (key points, edges, earlier features' axes
and sizes), in the face's 2D frame: read by the regularization (inference) and drawn
from by the data generator's regular samples (datagen/regular.py)."""
from __future__ import annotations

from dataclasses import dataclass

import cadquery as cq
import numpy as np

from .faces import FaceFrame

# Target names that callers pick targets by (the snap messages show every name).
FACE_EDGE = "a face edge"
CENTRE_LINE = "the face's centre line"
ROUND_AXIS = "the axis of an earlier round feature"


@dataclass(frozen=True)
class SnapTargets:
    """What a feature on the base face may snap to, in the face's 2D frame (mm)."""

    points: list[tuple[np.ndarray, str]]               # key points and earlier axes
    lines: list[tuple[np.ndarray, np.ndarray, str]]    # point, unit direction, name
    sizes: list[tuple[float, str]]                     # earlier lengths
    radii: list[tuple[float, str]]                     # earlier circles' radii
    origin: np.ndarray                                 # the face's centre: grid origin
    axes: tuple[np.ndarray, np.ndarray]                # grid directions: along f's edges


def _circle(edge: cq.Edge) -> tuple[np.ndarray, np.ndarray, float]:
    """A circular edge's centre, axis and radius."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    c = BRepAdaptor_Curve(edge.wrapped).Circle()
    loc, ax = c.Location(), c.Axis().Direction()
    return np.array([loc.X(), loc.Y(), loc.Z()]), np.array([ax.X(), ax.Y(), ax.Z()]), c.Radius()


def snap_targets(solid: cq.Shape, face: cq.Face, frame: FaceFrame) -> SnapTargets:
    """The base face's corners, edge midpoints, centre and centre lines, and the model's
    circle centres (on axes along n_f), vertices, edges parallel to f and sizes, all
    projected along n_f onto f's plane. The face's own come first: they win ties."""
    n = frame.normal
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
    points += [(p, "a corner of the face")
               for p in frame.to_2d(np.array([v.toTuple() for v in face.Vertices()]))]
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
    first = next((d for _, d, name in lines if name == FACE_EDGE), np.array([1.0, 0.0]))
    return SnapTargets(points, lines, sizes, radii, centre,
                       (first, np.array([-first[1], first[0]])))
