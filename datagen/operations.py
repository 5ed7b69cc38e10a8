# SPDX-License-Identifier: LGPL-2.1-or-later
"""Random instances of the operators on a given planar face (paper, "Sequence
generation": random base faces, offsets over a large range, polygons and circles centred
randomly inside the face, polygons and profiles perturbed without self-intersection).

Lengths are in mm, points and vectors in the world frame. The paper states its ranges
for a model whose diagonal is 1; here every absolute length is that fraction times
`DIAG`, the base box's diagonal (100 mm), and sizes on a face are fractions of the
face's own size (the square root of its area), so small faces get small primitives.

A sampler returns None when the face offers nothing to build on (no room for a centre,
no bevel corner); the caller then draws another face.
"""

from __future__ import annotations

import cadquery as cq
import numpy as np

from Sketch2CADWorkbench.brep.corners import BevelCorner, bevel_corners
from Sketch2CADWorkbench.brep.faces import ResolvedFace, face_ref_of, inside_face
from Sketch2CADWorkbench.brep.geometry import bezier_points, plane_basis
from Sketch2CADWorkbench.brep.protocol import (
    AddSubPrism,
    Bevel,
    Extrude,
    FaceRef,
    Mode,
    Operation,
    OperationError,
    OperatorType,
    Shell,
    Sweep,
    per_operator,
    straight_profile,
)
from Sketch2CADWorkbench.sketch.curves import rim_wires

DIAG = 100.0  # the base box's diagonal (mm): the paper's unit length

EXTRUDE_D = (0.03, 0.4)  # |d| / DIAG, either sign
PRISM_RADIUS = (0.08, 0.35)  # polygon circumradius / face size
PRISM_D = (0.04, 0.35)  # d / DIAG
SWEEP_RADIUS = (0.06, 0.3)  # r0 / face size
SWEEP_D = (0.04, 0.35)  # d / DIAG
BEVEL_SPAN = (0.1, 0.5)  # where l meets each edge, as a share of that edge from c
# t / DIAG: walls 2 to 12 mm on the 100 mm box (docs/measurements.md, operations.SHELL_T)
SHELL_T = (0.02, 0.12)
CENTRE_TRIES = 30


class PlanarFace:
    """A planar face of the current solid to sketch on: the face, its outward unit
    normal n_f, and (made on first use, then kept: a context's faces serve every sample
    of its block) its FaceRef for the protocol and the compound of its edges."""

    def __init__(self, face: cq.Face, normal: np.ndarray):
        self.face = face
        self.normal = normal
        self._ref: FaceRef | None = None
        self._outline: cq.Compound | None = None

    @property
    def ref(self) -> FaceRef:
        if self._ref is None:
            self._ref = face_ref_of(self.face)
        return self._ref

    def resolved(self) -> ResolvedFace:
        """f as the operators resolve `ref` on the solid it was drawn on."""
        return ResolvedFace.of(self.face)

    def edge_distance(self, point: np.ndarray) -> float:
        """The distance (mm) from a point to f's edges."""
        if self._outline is None:
            self._outline = cq.Compound.makeCompound(self.face.Edges())
        return self._outline.distance(cq.Vertex.makeVertex(*point))


def face_size(face: cq.Face) -> float:
    """The face's size (mm): the square root of its area."""
    return float(np.sqrt(face.Area()))


def plane_frame(n: np.ndarray, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A randomly rotated orthonormal basis (u, v) of the plane with normal n."""
    a, b = plane_basis(n)
    t = rng.uniform(0, 2 * np.pi)
    return np.cos(t) * a + np.sin(t) * b, -np.sin(t) * a + np.cos(t) * b


def random_centre(f: PlanarFace, rng: np.random.Generator, margin: float) -> np.ndarray | None:
    """A uniformly random point of a planar face at least `margin` mm from its edges
    (None if CENTRE_TRIES draws find none)."""
    u0, u1, v0, v1 = f.face.uvBounds()
    for _ in range(CENTRE_TRIES):
        p = np.array(f.face.positionAt(rng.uniform(u0, u1), rng.uniform(v0, v1)).toTuple())
        if inside_face(f.face, p) and f.edge_distance(p) >= margin:
            return p
    return None


# ----------------------------------------------------------------- extrude


def sample_extrude(rng: np.random.Generator, solid: cq.Shape, f: PlanarFace) -> Operation | None:
    """Move f out (d > 0) or in (d < 0) by a random offset."""
    d = rng.uniform(*EXTRUDE_D) * DIAG * rng.choice([-1.0, 1.0])
    return Extrude(f.ref, float(d))


# ----------------------------------------------------------------- add/subtract


def random_polygon(rng: np.random.Generator, k: int, radius: float) -> np.ndarray:
    """A regular-ish k-gon (k, 2) around the origin, never self-intersecting.

    Either exactly regular, or with each vertex's angle jittered within its own sector
    and its radius scaled: the vertices stay in angular order around the centre, so the
    polygon is star-shaped about it and simple. Half the time the shape is then
    stretched along one axis (rectangles, isosceles triangles); an affine map keeps a
    simple polygon simple.
    """
    ang = 2 * np.pi * np.arange(k) / k
    rad = np.full(k, radius)
    if rng.random() >= 0.4:
        ang = ang + rng.uniform(-0.3, 0.3, k) * 2 * np.pi / k
        rad = rad * rng.uniform(0.7, 1.3, k)
    pts = np.stack([rad * np.cos(ang), rad * np.sin(ang)], axis=1)
    if rng.random() < 0.5:
        pts[:, 0] *= rng.uniform(0.5, 1.5)
    return pts


def sample_prism(rng: np.random.Generator, solid: cq.Shape, f: PlanarFace) -> Operation | None:
    """A right prism on a 3- to 6-gon centred randomly inside f, added or subtracted."""
    r = rng.uniform(*PRISM_RADIUS) * face_size(f.face)
    c = random_centre(f, rng, 0.3 * r)
    if c is None:
        return None
    u, v = plane_frame(f.normal, rng)
    q = random_polygon(rng, int(rng.integers(3, 7)), r)
    poly = c + q[:, :1] * u + q[:, 1:] * v
    mode = Mode.ADD if rng.random() < 0.5 else Mode.SUBTRACT
    return AddSubPrism(
        f.ref, tuple(tuple(map(float, p)) for p in poly), float(rng.uniform(*PRISM_D) * DIAG), mode
    )


# ----------------------------------------------------------------- sweep


def sample_sweep(rng: np.random.Generator, solid: cq.Shape, f: PlanarFace) -> Operation | None:
    """A body of revolution on a circle centred randomly inside f, added or subtracted.

    40% cylinders (straight profile, equal radii), 20% cones, 40% curved profiles whose
    inner Bezier control points are perturbed off the straight line; control radii stay
    positive, so the profile (inside their convex hull) never reaches the axis.
    """
    r0 = rng.uniform(*SWEEP_RADIUS) * face_size(f.face)
    c = random_centre(f, rng, 0.2 * r0)
    if c is None:
        return None
    d = rng.uniform(*SWEEP_D) * DIAG
    shape = rng.random()
    r1 = r0 if shape < 0.4 else r0 * rng.uniform(0.4, 1.6)
    if shape < 0.6:
        inner = straight_profile(r0, r1, d)
    else:
        h = np.sort(rng.uniform(0.1, 0.9, 2)) * d
        on_line = r0 + (r1 - r0) * h / d
        inner = tuple(
            (float(b * rng.uniform(0.5, 1.6)), float(hh)) for b, hh in zip(on_line, h, strict=False)
        )
    mode = Mode.ADD if rng.random() < 0.5 else Mode.SUBTRACT
    return Sweep(
        f.ref,
        tuple(map(float, c)),
        float(r0),
        float(r1),
        float(d),
        tuple((float(a), float(b)) for a, b in inner),
        mode,
    )


# ----------------------------------------------------------------- bevel


def bevel_profile(rng: np.random.Generator, corner: BevelCorner) -> np.ndarray:
    """The four control points (4, 3) of a random profile l around corner c.

    l runs from a point of one edge to a point of the other, at random distances from
    c. 20% are straight chamfers; 55% bulge out towards c with inner control points on
    the edges (tangent to both sides, like a fillet; 0.55 of the way to c is close to a
    circular arc on a right angle); 25% bulge mildly in, away from c. Either way the
    control polygon is convex and stays in the wedge between the edges, so l neither
    crosses itself nor the edges.
    """
    pa = corner.c + corner.a * rng.uniform(*BEVEL_SPAN) * corner.la
    pb = corner.c + corner.b * rng.uniform(*BEVEL_SPAN) * corner.lb
    style = rng.random()
    if style < 0.2:
        k = 0.0
        inner = (pa + (pb - pa) / 3, pa + 2 * (pb - pa) / 3)
    elif style < 0.75:
        k = rng.uniform(0.2, 0.8)
        inner = (pa + k * (corner.c - pa), pb + k * (corner.c - pb))
    else:
        away = (pa + pb) / 2 - corner.c  # from c towards the chord, into the solid
        k = rng.uniform(0.1, 0.4)
        inner = (pa + (pb - pa) / 3 + k * away, pa + 2 * (pb - pa) / 3 + k * away)
    return np.stack([pa, inner[0], inner[1], pb])


def sample_bevel(rng: np.random.Generator, solid: cq.Shape, f: PlanarFace) -> Operation | None:
    """Round or chamfer a random convex corner of f along its crease."""
    corners = bevel_corners(solid, f.face, f.normal, 1e-6 * DIAG)
    if not corners:
        return None
    corner = corners[int(rng.integers(len(corners)))]
    ctrl = bevel_profile(rng, corner)
    return Bevel(
        f.ref,
        tuple(map(float, corner.c)),
        tuple(map(float, corner.opposite)),
        tuple(tuple(map(float, p)) for p in ctrl),
    )


# ----------------------------------------------------------------- shell


def sample_shell(rng: np.random.Generator, solid: cq.Shape, f: PlanarFace) -> Operation | None:
    """Open f and hollow the solid with walls of a random thickness t (the caller's
    Boolean check refuses a t the solid cannot take)."""
    return drawable_shell(f, float(rng.uniform(*SHELL_T) * DIAG))


def drawable_shell(f: PlanarFace, t: float) -> Shell | None:
    """The shell opening f with walls t thick, or None when f's outline inset by t leaves
    no rim to draw (f narrower than 2t)."""
    try:
        rim_wires(f.face, t)
    except OperationError:
        return None
    return Shell(f.ref, t)


# The sampler of each operator: (generator, solid, face f) -> operation or None.
SAMPLERS = per_operator(
    {
        OperatorType.EXTRUDE: sample_extrude,
        OperatorType.BEVEL: sample_bevel,
        OperatorType.ADDSUB: sample_prism,
        OperatorType.SWEEP: sample_sweep,
        OperatorType.SHELL: sample_shell,
    },
    "datagen.operations.SAMPLERS",
)


# ----------------------------------------------------------------- size bound


def _area(points: np.ndarray, n: np.ndarray) -> float:
    """Area (mm^2) of a planar polygon (K, 3) with normal n."""
    cross = np.cross(points, np.roll(points, -1, axis=0)).sum(axis=0)
    return 0.5 * abs(float(cross @ n))


def _extrude_volume(op: Extrude, f: PlanarFace) -> float:
    return f.face.Area() * abs(op.d)


def _prism_volume(op: AddSubPrism, f: PlanarFace) -> float:
    return _area(np.array(op.polygon), f.normal) * op.d


def _sweep_volume(op: Sweep, f: PlanarFace) -> float:
    rh = bezier_points(np.array(op.control_points(), float), 33)
    return float(np.pi * np.trapezoid(rh[:, 0] ** 2, rh[:, 1]))


def _bevel_volume(op: Bevel, f: PlanarFace) -> float:
    if op.across:  # around a rim or along a chain: no bound short of the Boolean
        return float("inf")
    region = np.concatenate([[op.corner], bezier_points(np.array(op.profile, float), 33)])
    return _area(region, f.normal) * float(np.linalg.norm(np.subtract(op.opposite, op.corner)))


def _shell_volume(op: Shell, f: PlanarFace) -> float:
    return np.inf  # the cavity is the solid's, not f's: no bound from f


# The volume (mm^3) of the primitive each operator adds or removes, from its face f.
PRIMITIVE_VOLUMES = per_operator(
    {
        OperatorType.EXTRUDE: _extrude_volume,
        OperatorType.BEVEL: _bevel_volume,
        OperatorType.ADDSUB: _prism_volume,
        OperatorType.SWEEP: _sweep_volume,
        OperatorType.SHELL: _shell_volume,
    },
    "datagen.operations.PRIMITIVE_VOLUMES",
)


def change_bound(op: Operation, f: PlanarFace) -> float:
    """An upper bound (mm^3) on how much `op` can change the solid's volume: the volume
    of the primitive it adds or removes (10% over, as sampled curves cut corners). Lets
    a too-small operation be rejected without running its Boolean."""
    return 1.1 * PRIMITIVE_VOLUMES[op.type](op, f)
