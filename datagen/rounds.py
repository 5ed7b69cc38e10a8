# SPDX-License-Identifier: LGPL-2.1-or-later
"""Rounds and chamfers drawn across an edge: bevel samples past the paper's corners.

`sample_round` draws, on a planar face f, an edge of f between f and another face where
the solid is convex (a straight edge, or a circular rim that a sweep left: the top of a
knob, the mouth of a hole; a rim RIM_SHARE of the time where the solid has one,
`round_faces`, and where f has one), a
point c on it, and a profile l across it in the plane normal to the edge at c, from f
to the face beyond: a fillet's arc (FILLET_SHARE), a chamfer's line of two widths
(CHAMFER_SHARE) or, along the drawn edge only, a freeform curve as the paper's bevels
draw them. The edge set is the drawn edge, its tangent chain or f's outline (EDGE_SET
odds; a freeform l follows the drawn edge, as the operator builds it). The sample's
view turns to face l's plane (`round_tangent`), as a designer turns the model to draw a
profile across an edge.
"""

from __future__ import annotations

import cadquery as cq
import numpy as np

from Sketch2CADWorkbench.brep.geometry import vec3
from Sketch2CADWorkbench.brep.protocol import Bevel, EdgeSet, Operation
from Sketch2CADWorkbench.brep.rounds import (
    edge_faces,
    faces_of,
    into_face,
    nearest_edge,
    point_on_edge,
)

from .operations import DIAG, PlanarFace

# The mix of round samples, set by rule (docs/measurements.md, rounds.RIM_SHARE, ...)
RIM_SHARE = 0.7  # of rounds on a solid with a circular rim, those drawn on a rim
FILLET_SHARE, CHAMFER_SHARE = 0.5, 0.3  # the rest are freeform profiles
EDGE_SET = {EdgeSet.DRAWN: 0.5, EdgeSet.CHAIN: 0.25, EdgeSet.OUTLINE: 0.25}
# A round's size (radius, chamfer width, a freeform profile's reach), of the model's
# diagonal; OCCT refuses one too large for the faces beside its edges, and the sampler
# then draws again.
SIZE_SPAN = (0.02, 0.08)
# Where along a straight edge l is drawn, from one end (of the edge's length): near an
# end, so that l' stands at the far end apart from it (sketch/curves.py).
ALONG_SPAN = (0.1, 0.3)
# A 4/3 (sqrt 2 - 1) handle draws a quarter circle: the freeform profiles bulge between
# a chamfer (0) and past a fillet.
FREEFORM_HANDLE = (0.0, 0.8)


def round_faces(rng: np.random.Generator, faces: list[PlanarFace]) -> list[PlanarFace]:
    """The faces a round is drawn on: with probability RIM_SHARE, where the solid has
    them, those bounded by a whole circular rim (a sweep's top, a hole's mouth); else
    every face."""
    rims = [
        f for f in faces if any(e.geomType() == "CIRCLE" and e.IsClosed() for e in f.face.Edges())
    ]
    return rims if rims and rng.random() < RIM_SHARE else faces


def sample_round(rng: np.random.Generator, solid: cq.Shape, f: PlanarFace) -> Operation | None:
    """A round, chamfer or freeform profile across an edge of f (module docstring), or
    None when f has no convex straight edge or rim between it and another face."""
    faces_map = edge_faces(solid)
    edges = [
        e
        for e in f.face.Edges()
        if (e.geomType() == "LINE" or (e.geomType() == "CIRCLE" and e.IsClosed()))
        and len(faces_of(faces_map, e)) == 2
    ]
    rims = [e for e in edges if e.geomType() == "CIRCLE"]
    pool = rims if rims and rng.random() < RIM_SHARE else edges
    if not pool:
        return None
    edge = pool[int(rng.integers(len(pool)))]
    if edge.geomType() == "LINE":
        at = rng.uniform(*ALONG_SPAN)
        at = at if rng.random() < 0.5 else 1 - at
    else:
        at = rng.uniform(0, 1)
    c, t = point_on_edge(edge, np.array(edge.positionAt(at).toTuple()))
    other = next(g for g in faces_of(faces_map, edge) if not g.wrapped.IsSame(f.face.wrapped))
    u_f = into_face(f.face, c, t, 1e-3 * DIAG)
    u_g = into_face(other, c, t, 1e-3 * DIAG)
    if u_f is None or u_g is None:
        return None
    if not cq.Solid(solid.wrapped).isInside(cq.Vector(*(c + 1e-3 * DIAG * (u_f + u_g)))):
        return None  # a concave edge: the sampled profiles cut convex ones
    size = rng.uniform(*SIZE_SPAN) * DIAG
    style = rng.random()
    which = list(EDGE_SET)[rng.choice(len(EDGE_SET), p=list(EDGE_SET.values()))]
    wedge = float(np.arccos(np.clip(u_f @ u_g, -1.0, 1.0)))
    if style < FILLET_SHARE:
        reach = size / np.tan(wedge / 2)
        handle = 4 / 3 * np.tan((np.pi - wedge) / 4) * size
        p0, p3 = c + reach * u_f, c + reach * u_g
        ctrl = [p0, p0 - handle * u_f, p3 - handle * u_g, p3]
        shape: dict = {"radius": float(size)}
    elif style < FILLET_SHARE + CHAMFER_SHARE:
        a, b = size, size * rng.uniform(0.5, 2.0)
        p0, p3 = c + a * u_f, c + b * u_g
        ctrl = [p0, p0 + (p3 - p0) / 3, p0 + 2 * (p3 - p0) / 3, p3]
        shape = {"distances": (float(a), float(b))}
    else:
        a, b = size, size * rng.uniform(0.5, 2.0)
        k = rng.uniform(*FREEFORM_HANDLE, 2)
        p0, p3 = c + a * u_f, c + b * u_g
        ctrl = [p0, p0 - k[0] * a * u_f, p3 - k[1] * b * u_g, p3]
        shape, which = {}, EdgeSet.DRAWN
    p0, p1, p2, p3 = (vec3(p) for p in ctrl)
    return Bevel(f.ref, vec3(c), None, (p0, p1, p2, p3), which, **shape)


def round_tangent(face: cq.Face, op: Operation) -> np.ndarray | None:
    """The tangent of the edge a bevel's profile is drawn across, on its face f (None
    for other operations): the view's azimuth runs along it (datagen/views.py)."""
    if not (isinstance(op, Bevel) and op.across):
        return None
    c = np.asarray(op.corner, float)
    return point_on_edge(nearest_edge(face, c)[0], c)[1]
