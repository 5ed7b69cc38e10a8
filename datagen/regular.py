# SPDX-License-Identifier: LGPL-2.1-or-later
"""Regular operations: parameters as a designer sets them (beyond the paper).

`sketch2cad datagen --regular-share P` draws that share of the operations with these
samplers instead of datagen/operations.py's random ones, to measure on held-out data
whether regularization (inference/fitting/regularize.py) recovers what a designer meant.
The regular values are the ones the snapping is built to recover, taken from the same
`snap_targets` it computes on the base face:

- lengths (extrusion and prism d, rectangle sides, sweep radii and d, bevel spans) are
  multiples of GRID mm, or (a share SAME_SIZE) equal to an earlier edge length or radius
  of the model;
- prisms and sweeps stand on f's centre, on one of its centre lines at a whole number of
  mm from the centre, or (where an earlier round feature's axis crosses f) concentric
  with it;
- prism outlines are exact rectangles or regular polygons with a side along f's first
  straight edge (the direction the snapping aligns to and lays its grid along);
- sweep profiles are straight (cylinders and cones); bevels cut both edges equally, as
  a chamfer or a round.

The samplers have the signature of operations.SAMPLERS and return None when f offers no
regular placement; the caller's checks (the Boolean builds, the volume changes enough)
apply as to any operation.
"""

from __future__ import annotations

import cadquery as cq
import numpy as np

from Sketch2CADWorkbench.brep.corners import bevel_corners
from Sketch2CADWorkbench.brep.faces import FaceFrame, inside_face
from Sketch2CADWorkbench.brep.protocol import (
    AddSubPrism,
    Bevel,
    Extrude,
    Mode,
    Operation,
    OperatorType,
    Sweep,
    per_operator,
    straight_profile,
)
from Sketch2CADWorkbench.brep.snap_targets import (
    CENTRE_LINE,
    ROUND_AXIS,
    SnapTargets,
    snap_targets,
)

from .operations import (
    BEVEL_SPAN,
    DIAG,
    EXTRUDE_D,
    PRISM_D,
    PRISM_RADIUS,
    SHELL_T,
    SWEEP_D,
    SWEEP_RADIUS,
    PlanarFace,
    drawable_shell,
    face_size,
)

GRID = 1.0  # mm: the step regular lengths and offsets are multiples of; the
# held-out measure snaps with `--snap-step 1` (docs/measurements.md, regular.GRID)
SAME_SIZE = 0.2  # share of lengths taken equal to an earlier one, where one fits
CONCENTRIC = 0.5  # share of centres on an earlier round feature's axis, where one is
ON_CENTRE = 0.5  # of the other centres: f's centre; the rest on a centre line
RECTANGLE = 0.5  # share of prism outlines that are rectangles (else regular k-gons)
CYLINDER = 0.6  # share of regular sweeps with equal radii (else cones)
CHAMFER = 0.4  # share of regular bevels that are straight (else rounds)
ROUND_K = 0.55  # a round's inner control points 0.55 of the way to c: near a
# circular arc on a right angle (operations.bevel_profile)


def on_grid(length: float) -> float:
    """`length` (mm, > 0) rounded to the GRID, at least one step."""
    return max(GRID, round(length / GRID) * GRID)


def regular_length(
    rng: np.random.Generator, lo: float, hi: float, earlier: list[tuple[float, str]]
) -> float:
    """A length in [lo, hi] mm: one of the `earlier` sizes in that range (a share
    SAME_SIZE of the time, when there is one), else a uniform draw rounded to the GRID."""
    fits = [s for s, _ in earlier if lo <= s <= hi]
    if fits and rng.random() < SAME_SIZE:
        return float(fits[int(rng.integers(len(fits)))])
    return on_grid(rng.uniform(lo, hi))


def regular_centre(
    rng: np.random.Generator, f: PlanarFace, frame: FaceFrame, targets: SnapTargets, margin: float
) -> np.ndarray | None:
    """A centre (2D, f's frame) where a designer puts a feature: on an earlier round
    feature's axis, on f's centre, or on one of f's centre lines at a whole number of
    GRID steps from it; at least `margin` mm inside f (None when the drawn place is not).
    """
    axes = [p for p, name in targets.points if name == ROUND_AXIS]
    if axes and rng.random() < CONCENTRIC:
        c = axes[int(rng.integers(len(axes)))]
    elif rng.random() < ON_CENTRE:
        c = targets.origin
    else:
        lines = [d for _, d, name in targets.lines if name == CENTRE_LINE] or list(targets.axes)
        d = lines[int(rng.integers(len(lines)))]
        t = GRID * round(rng.uniform(-0.35, 0.35) * face_size(f.face) / GRID)
        c = targets.origin + t * d
    p = frame.to_3d(c)[0]
    if not inside_face(f.face, p) or f.edge_distance(p) < margin:
        return None
    return np.asarray(c, float)


def _setting(f: PlanarFace, solid: cq.Shape) -> tuple[FaceFrame, SnapTargets]:
    """f's frame and what the snapping would snap to on it (brep.snap_targets)."""
    frame = FaceFrame.of(f.face)
    return frame, snap_targets(solid, f.face, frame)


def regular_polygon(rng: np.random.Generator, r: float, targets: SnapTargets) -> np.ndarray:
    """A prism outline (k, 2) about the origin with a side along f's first straight edge:
    a rectangle whose sides are regular lengths, or a regular 3- to 6-gon of
    circumradius about r whose side is a GRID multiple."""
    e1, e2 = targets.axes
    if rng.random() < RECTANGLE:
        a, b = (regular_length(rng, 0.6 * r, 1.8 * r, targets.sizes) / 2 for _ in range(2))
        return np.array([-a * e1 - b * e2, a * e1 - b * e2, a * e1 + b * e2, -a * e1 + b * e2])
    k = int(rng.integers(3, 7))
    side = on_grid(2 * r * np.sin(np.pi / k))
    radius = side / (2 * np.sin(np.pi / k))
    # vertex angles measured from e1 so that the first side (vertex 0 to 1) runs along e1
    ang = -np.pi / 2 - np.pi / k + 2 * np.pi * np.arange(k) / k
    return radius * (np.cos(ang)[:, None] * e1 + np.sin(ang)[:, None] * e2)


# ----------------------------------------------------------------- samplers


def regular_extrude(rng: np.random.Generator, solid: cq.Shape, f: PlanarFace) -> Operation | None:
    """f moved out or in by a regular length."""
    _, targets = _setting(f, solid)
    d = regular_length(rng, EXTRUDE_D[0] * DIAG, EXTRUDE_D[1] * DIAG, targets.sizes)
    return Extrude(f.ref, float(d * rng.choice([-1.0, 1.0])))


def regular_prism(rng: np.random.Generator, solid: cq.Shape, f: PlanarFace) -> Operation | None:
    """A rectangle or regular polygon aligned with f's edges, placed regularly, of a
    regular depth, added or subtracted."""
    frame, targets = _setting(f, solid)
    r = rng.uniform(*PRISM_RADIUS) * face_size(f.face)
    c = regular_centre(rng, f, frame, targets, 0.3 * r)
    if c is None:
        return None
    poly = frame.to_3d(c + regular_polygon(rng, r, targets))
    d = regular_length(rng, PRISM_D[0] * DIAG, PRISM_D[1] * DIAG, targets.sizes)
    mode = Mode.ADD if rng.random() < 0.5 else Mode.SUBTRACT
    return AddSubPrism(f.ref, tuple(tuple(map(float, p)) for p in poly), float(d), mode)


def regular_sweep(rng: np.random.Generator, solid: cq.Shape, f: PlanarFace) -> Operation | None:
    """A cylinder or cone of regular radii and length, placed regularly, added or
    subtracted."""
    frame, targets = _setting(f, solid)
    size = face_size(f.face)
    lo, hi = SWEEP_RADIUS[0] * size, SWEEP_RADIUS[1] * size
    r0 = regular_length(rng, lo, hi, targets.radii)
    c = regular_centre(rng, f, frame, targets, 0.2 * r0)
    if c is None:
        return None
    r1 = r0 if rng.random() < CYLINDER else regular_length(rng, 0.4 * r0, 1.6 * r0, targets.radii)
    d = regular_length(rng, SWEEP_D[0] * DIAG, SWEEP_D[1] * DIAG, targets.sizes)
    mode = Mode.ADD if rng.random() < 0.5 else Mode.SUBTRACT
    return Sweep(
        f.ref,
        tuple(map(float, frame.to_3d(c)[0])),
        float(r0),
        float(r1),
        float(d),
        straight_profile(r0, r1, d),
        mode,
    )


def regular_bevel(rng: np.random.Generator, solid: cq.Shape, f: PlanarFace) -> Operation | None:
    """A chamfer or round of a convex corner of f, cutting both edges by the same
    GRID-multiple distance."""
    corners = bevel_corners(solid, f.face, f.normal, 1e-6 * DIAG)
    if not corners:
        return None
    corner = corners[int(rng.integers(len(corners)))]
    short = min(corner.la, corner.lb)
    s = on_grid(rng.uniform(*BEVEL_SPAN) * short)
    if s >= short:
        return None  # the edge is shorter than one grid step past the span
    pa, pb = corner.c + s * corner.a, corner.c + s * corner.b
    if rng.random() < CHAMFER:
        inner = (pa + (pb - pa) / 3, pa + 2 * (pb - pa) / 3)
    else:
        inner = (pa + ROUND_K * (corner.c - pa), pb + ROUND_K * (corner.c - pb))
    return Bevel(
        f.ref,
        tuple(map(float, corner.c)),
        tuple(map(float, corner.opposite)),
        tuple(tuple(map(float, p)) for p in (pa, *inner, pb)),
    )


def regular_shell(rng: np.random.Generator, solid: cq.Shape, f: PlanarFace) -> Operation | None:
    """Walls a whole number of grid steps thick."""
    return drawable_shell(f, on_grid(rng.uniform(*SHELL_T) * DIAG))


# The regular sampler of each operator, as operations.SAMPLERS.
REGULAR_SAMPLERS = per_operator(
    {
        OperatorType.EXTRUDE: regular_extrude,
        OperatorType.BEVEL: regular_bevel,
        OperatorType.ADDSUB: regular_prism,
        OperatorType.SWEEP: regular_sweep,
        OperatorType.SHELL: regular_shell,
    },
    "datagen.regular.REGULAR_SAMPLERS",
)
