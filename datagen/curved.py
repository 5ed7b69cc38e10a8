# SPDX-License-Identifier: LGPL-2.1-or-later
"""Samples whose last operation stands on a curved face (beyond the paper): a prism
or a sweep on the side of a cylinder or cone that an earlier sweep made, or that side
extruded (its radius changed).

The context is a random sequence (0 to 2 operations, datagen/sequences.py) followed by
an added straight sweep (a cylinder or a cone); the last operation is drawn on that
sweep's side at a random point of it, in the tangent plane there (brep/protocol), with
sizes relative to the side's radius so that the primitive fits across it, and its
outline on the side (not overhanging its rims). A candidate too small to change the
solid's volume by MIN_VOLUME_CHANGE is rejected before its Booleans by an upper bound on
that change (`change_bound_on_curved`), so the samples are those the Booleans alone
would accept. A sample is then made as any other (datagen/generate.view_sample): an
informative view, strokes from the operation's curves, the face label on the curved face.

`write_curved_set` writes such a data set in the data set format (datagen/dataset.py),
one worker, a noise level or the levels taking turns ("mix"): held-out sets to measure
operators on curved faces, and the curved part of the head's training data
(`sketch2cad datagen --curved ...`).
"""

from __future__ import annotations

import sys
from pathlib import Path

import cadquery as cq
import numpy as np
from tqdm import tqdm

from Sketch2CADWorkbench.brep.faces import (
    CurvedSurface,
    OperationError,
    ResolvedFace,
    face_ref_at,
    is_curved,
    model_scale,
    points_on_face,
)
from Sketch2CADWorkbench.brep.geometry import plane_basis
from Sketch2CADWorkbench.brep.operators import REACH_MARGIN_REL, operation_result
from Sketch2CADWorkbench.brep.protocol import (
    AddSubPrism,
    Extrude,
    FaceRef,
    Mode,
    Operation,
    OperatorType,
    Sweep,
    straight_profile,
)
from Sketch2CADWorkbench.render.maps import MapRenderer

from .dataset import write_shard
from .generate import IMAGE_SIZE, Context, sample_rng, view_sample
from .operations import (
    DIAG,
    PRIMITIVE_VOLUMES,
    PRISM_D,
    SWEEP_D,
    random_polygon,
)
from .parallel import (
    SHARD_SIZE,
    DatagenSettings,
    manifest_of,
    noise_of_block,
    open_set_folder,
)
from .sample import Sample
from .sequences import MIN_VOLUME_CHANGE, Drawn, Sequence, Stage, sample_operation, sample_sequence

# The last operation's type on a curved face: prisms and sweeps as 4:2 (the paper's
# shares of the two), and extrusions of the side 1.
CURVED_WEIGHTS = {OperatorType.ADDSUB: 4, OperatorType.SWEEP: 2, OperatorType.EXTRUDE: 1}
ACROSS = (0.25, 0.6)  # a primitive's half-width across the axis / the side's radius
TRIES = 40
# Sides of the polygon, circumscribing a sweep's circle c0, whose corners bound how far
# below the tangent plane the surface lies under c0.
RING_SIDES = 16
# Over the primitive volume, as `change_bound`: sampled outlines cut corners, and OCCT's
# volumes carry noise.
BOUND_SLACK = 1.1


class CurvedFace:
    """A cylinder's or cone's side to sketch on, at a chosen point p_f of it."""

    def __init__(self, face: cq.Face, ref: FaceRef):
        self.face = face
        self.ref = ref
        self.normal = np.asarray(ref.normal, float)
        self.surface = CurvedSurface.of(face)

    def resolved(self) -> ResolvedFace:
        """f as the operators resolve `ref` on the solid it was drawn on."""
        return ResolvedFace(
            self.face, self.normal, 0.0, self.surface, np.asarray(self.ref.point, float)
        )


def _point_on(face: cq.Face, rng: np.random.Generator, margin: float) -> np.ndarray | None:
    """A random point of the face, away from its ends along the axis by `margin` of the
    parameter range (so a primitive there does not overhang the side's rims)."""
    u0, u1, v0, v1 = face.uvBounds()
    span = v1 - v0
    if span <= 0:
        return None
    u = rng.uniform(u0, u1)
    v = rng.uniform(v0 + margin * span, v1 - margin * span)
    p = face._geomAdaptor().Value(u, v)
    return np.array(p.Coord())


def sample_on_curved(
    rng: np.random.Generator, face: cq.Face, kind: OperatorType
) -> tuple[Operation, CurvedFace] | None:
    """An operation of `kind` on the curved face at a random point of it."""
    p = _point_on(face, rng, 0.3)
    if p is None:
        return None
    f = CurvedFace(face, face_ref_at(face, p))
    if not f.surface.convex:
        return None  # the bores a subtraction makes are seen from inside: not sketched
    radius = float(f.surface.radius_at(f.ref.point))
    if kind is OperatorType.EXTRUDE:
        d = rng.uniform(0.15, 0.5) * radius * rng.choice([-1.0, 1.0])
        return Extrude(f.ref, float(d)), f
    half = rng.uniform(*ACROSS) * radius
    mode = Mode.ADD if rng.random() < 0.5 else Mode.SUBTRACT
    d = rng.uniform(*PRISM_D) * DIAG
    if mode is Mode.SUBTRACT:
        d = min(d, 0.8 * radius)  # a slot or hole, not a cut through the whole body
    centre = np.asarray(f.ref.point)
    # the axis direction in the tangent plane, and across it
    along = f.surface.axis - (f.surface.axis @ f.normal) * f.normal
    along /= np.linalg.norm(along)
    across = np.cross(f.normal, along)
    if kind is OperatorType.ADDSUB:
        q = random_polygon(rng, int(rng.integers(3, 7)), half)
        q *= half / np.abs(q[:, 0]).max()  # its half-width across the axis is `half`
        poly = centre + q[:, :1] * across + q[:, 1:] * along
        if not _on_face(f, poly):
            return None
        return AddSubPrism(f.ref, tuple(tuple(map(float, v)) for v in poly), float(d), mode), f
    r0 = half
    ring = np.linspace(0, 2 * np.pi, 16, endpoint=False)
    if not _on_face(
        f, centre + r0 * (np.outer(np.cos(ring), across) + np.outer(np.sin(ring), along))
    ):
        return None
    r1 = r0 if rng.random() < 0.6 else r0 * rng.uniform(0.5, 1.4)
    d = min(d, rng.uniform(*SWEEP_D) * DIAG) if mode is Mode.ADD else d
    return Sweep(
        f.ref,
        tuple(map(float, centre)),
        float(r0),
        float(r1),
        float(d),
        straight_profile(r0, r1, d),
        mode,
    ), f


def _on_face(f: CurvedFace, outline: np.ndarray) -> bool:
    """Whether an outline on the tangent plane, carried along n_f onto the surface, lies
    on f: a primitive overhanging the side's rims is not what a designer sketches."""
    t = f.surface.crossings(outline, f.normal, model_scale(f.face))
    if np.isnan(t).any():
        return False
    on = outline + t[:, None] * f.normal
    return bool(points_on_face(f.face, on, 1e-6 * model_scale(f.face), boundary=False).all())


def change_bound_on_curved(op: Operation, f: CurvedFace, scale: float) -> float:
    """An upper bound (mm^3) on how much `op` on the curved f can change the volume of a
    solid of size `scale` (mm), as `change_bound` for a planar f: lets most candidates,
    whose primitive is too small for the solid, be rejected without their Booleans.

    A prism or sweep changes it by at most its primitive before brep/operators clips it
    to f's surface: the part above the tangent plane T plus its footprint on T times how
    far it reaches below T (an addition reaches down to the surface under the footprint,
    a subtraction starts just above T). f is convex (a subtraction's bore is not drawn
    on), so how far the surface lies below T is a convex function on T and is largest at
    a corner of the footprint, or of a polygon around c0. An extrusion of a cylinder's
    side moves it by d away from the axis (d < 0: toward it): a shell of f's area A
    times |d| (1 + d / 2r). A cone's is not bounded here (infinite): its Boolean decides.
    """
    surface = f.surface
    if op.type is OperatorType.EXTRUDE:
        if surface.slope != 0.0:
            return float("inf")
        outward = op.d if surface.convex else -op.d  # how far the surface leaves the axis
        return BOUND_SLACK * f.face.Area() * abs(op.d) * (1.0 + outward / (2.0 * surface.radius))
    volume = PRIMITIVE_VOLUMES[op.type](op, f)  # the part above T (it reads f's normal)
    if op.type is OperatorType.ADDSUB:
        corners, area = np.array(op.polygon, float), volume / op.d  # volume: area times d
    else:
        u, v = plane_basis(f.normal)
        ring = np.linspace(0, 2 * np.pi, RING_SIDES, endpoint=False)
        reach = op.r0 / np.cos(np.pi / RING_SIDES)  # the circumscribed polygon's corners
        corners = np.asarray(op.center) + reach * (
            np.outer(np.cos(ring), u) + np.outer(np.sin(ring), v)
        )
        area = np.pi * op.r0**2
    below = REACH_MARGIN_REL * scale
    if op.mode is Mode.ADD:
        t = surface.crossings(corners, f.normal, scale)
        if np.isnan(t).any():
            return float("inf")  # a corner past the surface: the Boolean decides
        below += max(0.0, -float(t.min()))
    return BOUND_SLACK * (volume + area * below)


def _straight_addition(op: Sweep) -> bool:
    return op.mode is Mode.ADD and np.allclose(op.profile, straight_profile(op.r0, op.r1, op.d))


def curved_context(rng: np.random.Generator) -> tuple[Sequence, list[cq.Face]]:
    """A random sequence ending in an added straight sweep (a cylinder or a cone), and
    the curved faces of its final solid. Sweeps of other kinds (subtracted, or with a
    curved profile: 70% of those drawn) are drawn again before their Booleans; each
    counts as one of sample_operation's tries, so a solid that admits few sweeps is
    given up a little sooner than when they were built and then thrown away."""
    while True:
        seq = sample_sequence(rng, int(rng.integers(0, 3)))
        for _ in range(TRIES):
            drawn = sample_operation(
                rng, seq.stages[-1], OperatorType.SWEEP, keep=_straight_addition
            )
            if drawn is None:
                break
            protocol = seq.protocol.append(drawn.op)
            stages = seq.stages + [drawn.result]
            faces = [f for f in drawn.result.solid.Faces() if is_curved(f)]
            if faces:
                return Sequence(protocol, stages), faces


def draw_kind(rng: np.random.Generator) -> OperatorType:
    kinds = list(CURVED_WEIGHTS)
    w = np.array([CURVED_WEIGHTS[k] for k in kinds], float)
    return kinds[rng.choice(len(kinds), p=w / w.sum())]


def curved_sample(
    rng: np.random.Generator, noise_level: int, renderer: MapRenderer, size: int = IMAGE_SIZE
) -> Sample:
    """One sample whose last operation stands on a cylinder's or cone's side."""
    kind = draw_kind(rng)
    while True:
        seq, faces = curved_context(rng)
        context = Context(seq)
        stage = seq.stages[-1]
        least, scale = MIN_VOLUME_CHANGE * stage.volume, model_scale(stage.solid)
        for _ in range(TRIES):
            got = sample_on_curved(rng, faces[int(rng.integers(len(faces)))], kind)
            if got is None or change_bound_on_curved(*got, scale) < least:
                continue  # rejected before paying for the Booleans
            op, f = got
            try:
                out = operation_result(stage.solid, op)
            except OperationError:
                continue
            result = Stage(out.solid, out.volume)
            if abs(result.volume - stage.volume) < least:
                continue
            sample = view_sample(rng, context, Drawn(op, f, result), noise_level, renderer, size)
            if sample is not None:
                return sample


def curved_settings(out: Path, count: int, seed: int, noise: str) -> DatagenSettings:
    """The settings of a curved set: one worker, shards of SHARD_SIZE (one shard of
    `count` when that is fewer)."""
    return DatagenSettings(
        Path(out), count, seed, noise, workers=1, shard_size=min(count, SHARD_SIZE)
    )


def write_curved_set(out: Path, count: int, seed: int, noise: str) -> int:
    """A data set of `count` curved-face samples (one worker), for held-out measures or
    for training the head; sample i is a function of (seed, i) and its noise level, with
    "mix" the levels taking turns per context as in planar sets (`noise_of_block`: a
    curved sample has a context of its own). Written shard by shard:
    a rerun keeps the complete shards and makes the rest. Returns the exit code."""
    settings = curved_settings(out, count, seed, noise)
    folder = open_set_folder(settings, {"curved": True})
    if isinstance(folder, str):
        print(f"sketch2cad datagen: error: {folder}", file=sys.stderr)
        return 2
    out, size, complete = settings.out, settings.shard_size, folder.complete
    renderer = MapRenderer()
    with tqdm(
        total=count,
        initial=sum(min(size, count - k * size) for k in complete),
        desc="curved samples",
        unit="sample",
    ) as bar:
        for k in range(len(manifest_of(settings, [])["shards"])):
            if k in complete:
                continue
            samples = []
            for i in range(k * size, min((k + 1) * size, count)):
                samples.append(
                    curved_sample(sample_rng(seed, i), noise_of_block(noise, i), renderer)
                )
                bar.update()
            write_shard(out, k, samples)
            folder.done(k)
    print(f"datagen: {count} samples on curved faces in {out}/")
    return 0
