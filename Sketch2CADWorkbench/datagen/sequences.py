# SPDX-License-Identifier: LGPL-2.1-or-later
"""Random modeling sequences (paper, "Sequence generation").

A sequence starts from a random box whose diagonal is 100 mm; the paper's ranges are
given for a unit-diagonal model, so every length below is a fraction of that diagonal
(`DIAG`). Operations are sampled uniformly over wide ranges on random planar faces;
results that fail, or barely change the solid, are rejected and drawn again.
"""
from __future__ import annotations

from dataclasses import dataclass

import cadquery as cq
import numpy as np

from ..brep.faces import OperationError, face_ref_of, planar_faces
from ..brep.operators import apply_operation, make_box
from ..brep.protocol import (AddSubPrism, Bevel, Box, Extrude, Mode, Operation, OperatorType,
                             Protocol, Sweep)

DIAG = 100.0
LAST_OP_WEIGHTS = {OperatorType.EXTRUDE: 1, OperatorType.BEVEL: 1, OperatorType.ADDSUB: 4,
                   OperatorType.SWEEP: 2}
MIN_VOLUME_CHANGE = 0.01  # of the solid's volume: smaller changes are degenerate
TRIES = 25


@dataclass
class Sequence:
    """A sampled protocol with the solid after each step (solids[0] is the box)."""

    protocol: Protocol
    solids: list[cq.Solid]


def random_box(rng: np.random.Generator) -> Box:
    s = rng.uniform(0.35, 1.0, 3)
    s *= DIAG / np.linalg.norm(s)
    return Box(tuple(float(round(x, 3)) for x in s))


def draw_type(rng: np.random.Generator) -> OperatorType:
    """An operator type with the paper's 1:1:4:2 frequencies."""
    types = list(LAST_OP_WEIGHTS)
    w = np.array([LAST_OP_WEIGHTS[t] for t in types], float)
    return types[rng.choice(len(types), p=w / w.sum())]


def _frame(n: np.ndarray, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A random orthonormal in-plane basis (u, v) for normal n."""
    a = np.cross(n, [1.0, 0, 0] if abs(n[0]) < 0.9 else [0, 1.0, 0])
    a /= np.linalg.norm(a)
    b = np.cross(n, a)
    t = rng.uniform(0, 2 * np.pi)
    return np.cos(t) * a + np.sin(t) * b, -np.sin(t) * a + np.cos(t) * b


def _interior_point(face: cq.Face, rng: np.random.Generator, margin: float) -> np.ndarray | None:
    """A uniformly random point of a planar face at least `margin` mm inside it."""
    u0, u1, v0, v1 = face.uvBounds()
    outline = cq.Compound.makeCompound(face.Edges())
    for _ in range(30):
        p = face.positionAt(rng.uniform(u0, u1), rng.uniform(v0, v1))
        vert = cq.Vertex.makeVertex(*p.toTuple())
        if face.distance(vert) < 1e-9 and outline.distance(vert) >= margin:
            return np.array(p.toTuple())
    return None


def _face_size(face: cq.Face) -> float:
    return float(np.sqrt(face.Area()))


def sample_extrude(rng, solid, face, n) -> Operation | None:
    d = rng.uniform(0.03, 0.4) * DIAG * rng.choice([-1.0, 1.0])
    return Extrude(face_ref_of(face), float(d))


def sample_prism(rng, solid, face, n) -> Operation | None:
    size = _face_size(face)
    r = rng.uniform(0.08, 0.35) * size
    c = _interior_point(face, rng, 0.3 * r)
    if c is None:
        return None
    u, v = _frame(n, rng)
    k = int(rng.integers(3, 7))
    # A perturbed regular N-gon: star-shaped about its centre, hence never self-intersecting.
    ang = 2 * np.pi * np.arange(k) / k + rng.uniform(-0.25, 0.25, k) * np.pi / k
    rad = r * rng.uniform(0.75, 1.25, k)
    if rng.random() < 0.4:  # regular shapes are common in designs
        ang, rad = 2 * np.pi * np.arange(k) / k, np.full(k, r)
    poly = [tuple(map(float, c + rr * (np.cos(a) * u + np.sin(a) * v))) for a, rr in zip(ang, rad)]
    mode = Mode.ADD if rng.random() < 0.5 else Mode.SUBTRACT
    return AddSubPrism(face_ref_of(face), tuple(poly), float(rng.uniform(0.04, 0.35) * DIAG), mode)


def sample_sweep(rng, solid, face, n) -> Operation | None:
    size = _face_size(face)
    r0 = rng.uniform(0.06, 0.3) * size
    c = _interior_point(face, rng, 0.2 * r0)
    if c is None:
        return None
    r1 = r0 if rng.random() < 0.5 else r0 * rng.uniform(0.4, 1.6)
    d = rng.uniform(0.04, 0.35) * DIAG
    if rng.random() < 0.5:
        inner = ((r0 + (r1 - r0) / 3, d / 3), (r0 + 2 * (r1 - r0) / 3, 2 * d / 3))
    else:
        h = np.sort(rng.uniform(0.1, 0.9, 2)) * d
        base = [r0 + (r1 - r0) * hh / d for hh in h]
        inner = tuple((float(b * rng.uniform(0.6, 1.5)), float(hh)) for b, hh in zip(base, h))
    mode = Mode.ADD if rng.random() < 0.5 else Mode.SUBTRACT
    return Sweep(face_ref_of(face), tuple(map(float, c)), float(r0), float(r1), float(d),
                 tuple((float(a), float(b)) for a, b in inner), mode)


def bevel_corners(solid: cq.Shape, face: cq.Face, n: np.ndarray):
    """Corners c of f usable for a bevel: two straight edges of f meet at c and a
    straight edge of the solid leaves c along -n_f. Yields (c, c', a_dir, b_dir, la, lb)."""
    tol = 1e-6 * DIAG
    edges = [(np.array(e.startPoint().toTuple()), np.array(e.endPoint().toTuple()))
             for e in face.Edges() if e.geomType() == "LINE"]
    creases = []
    for e in solid.Edges():
        if e.geomType() != "LINE":
            continue
        a, b = np.array(e.startPoint().toTuple()), np.array(e.endPoint().toTuple())
        for p, q in ((a, b), (b, a)):
            if float((q - p) @ n) / np.linalg.norm(q - p) < -0.999:
                creases.append((p, q))
    out = []
    for c, cp in creases:
        at_c = []
        for a, b in edges:
            if np.linalg.norm(a - c) < tol:
                at_c.append(b - a)
            elif np.linalg.norm(b - c) < tol:
                at_c.append(a - b)
        if len(at_c) == 2:
            la, lb = np.linalg.norm(at_c[0]), np.linalg.norm(at_c[1])
            cross = np.cross(at_c[0], at_c[1]) @ n
            if abs(cross) > 1e-6 * la * lb:  # not a straight-through vertex
                out.append((c, cp, at_c[0] / la, at_c[1] / lb, la, lb))
    return out


def sample_bevel(rng, solid, face, n) -> Operation | None:
    corners = bevel_corners(solid, face, n)
    if not corners:
        return None
    c, cp, da, db, la, lb = corners[int(rng.integers(len(corners)))]
    pa = c + da * rng.uniform(0.1, 0.45) * la
    pb = c + db * rng.uniform(0.1, 0.45) * lb
    k = rng.uniform(0.0, 0.8)  # 0: a straight chamfer, ~0.55: a round
    ctrl = (pa, pa + k * (c - pa), pb + k * (c - pb), pb)
    return Bevel(face_ref_of(face), tuple(map(float, c)), tuple(map(float, cp)),
                 tuple(tuple(map(float, p)) for p in ctrl))


_SAMPLERS = {OperatorType.EXTRUDE: sample_extrude, OperatorType.BEVEL: sample_bevel,
             OperatorType.ADDSUB: sample_prism, OperatorType.SWEEP: sample_sweep}


def sample_operation(rng: np.random.Generator, solid: cq.Solid, kind: OperatorType
                     ) -> tuple[Operation, cq.Solid] | None:
    """An operation of type `kind` on a random planar face that changes the solid, with
    its result; None when TRIES draws all fail."""
    faces = [f for f, _, _ in planar_faces(solid) if f.Area() > 1e-3 * DIAG ** 2]
    for _ in range(TRIES):
        face = faces[int(rng.integers(len(faces)))]
        n = np.array(face.normalAt().toTuple())
        op = _SAMPLERS[kind](rng, solid, face, n)
        if op is None:
            continue
        try:
            out = apply_operation(solid, op)
        except OperationError:
            continue
        if abs(out.Volume() - solid.Volume()) >= MIN_VOLUME_CHANGE * solid.Volume():
            return op, out
    return None


def sample_sequence(rng: np.random.Generator, length: int,
                    last: OperatorType | None = None) -> Sequence:
    """A protocol of `length` operations; the last one of type `last` (1:1:4:2 if None).

    The last type is drawn once, before any retry, so that types which fail more often
    keep their share.
    """
    last = last or draw_type(rng)
    if length == 0:
        box = random_box(rng)
        return Sequence(Protocol(box), [make_box(box)])
    while True:
        box = random_box(rng)
        solids = [make_box(box)]
        ops: list[Operation] = []
        for i in range(length):
            kind = last if i == length - 1 else draw_type(rng)
            got = sample_operation(rng, solids[-1], kind)
            if got is None:
                break
            ops.append(got[0])
            solids.append(got[1])
        if len(ops) == length:
            return Sequence(Protocol(box, tuple(ops)), solids)
