# SPDX-License-Identifier: LGPL-2.1-or-later
"""Random modeling sequences (paper, "Sequence generation").

A sequence starts from a random box and applies 1 to 4 random operations. The box's
diagonal is `DIAG` = 100 mm with a random aspect; the paper gives its ranges "for a
unit-diagonal model", so each of them is used here multiplied by the diagonal (see
datagen/operations.py). The last operation's type is drawn 1:1:4:2 (extrude : bevel :
add/sub : sweep) as in the paper; earlier operations, which only make the context, take
any type with equal odds.

An operation is drawn on a random planar face of the current solid and rejected, then
drawn again, when it cannot be built (OperationError: the result would be empty, fall
apart, or be invalid) or when it changes the solid's volume by less than
MIN_VOLUME_CHANGE. Everything is a function of the numpy Generator passed in.

With a `regular_share` P > 0, each operation is regular with probability P (drawn once
per operation from that generator, before its face): its parameters are then set as a
designer sets them (datagen/regular.py). P = 0 draws nothing for it, so the data is
the same as without the option.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import cadquery as cq
import numpy as np

from Sketch2CADWorkbench.brep.faces import OperationError, planar_faces
from Sketch2CADWorkbench.brep.operators import make_box, operation_result
from Sketch2CADWorkbench.brep.protocol import Box, Operation, OperatorType, Protocol, per_operator

from .operations import DIAG, SAMPLERS, PlanarFace, change_bound
from .regular import REGULAR_SAMPLERS
from .rounds import round_faces, sample_round

# A shell is drawn only where asked for (`with_shells`), so that data sets made without it
# stay the same.
LAST_OP_WEIGHTS = per_operator(
    {
        OperatorType.EXTRUDE: 1,
        OperatorType.BEVEL: 1,
        OperatorType.ADDSUB: 4,
        OperatorType.SWEEP: 2,
        OperatorType.SHELL: 0,
    },
    "datagen.sequences.LAST_OP_WEIGHTS",
)
EARLIER_OP_WEIGHTS = {t: 0 if t is OperatorType.SHELL else 1 for t in OperatorType}
BOX_SIDES = (0.35, 1.0)  # side lengths before scaling to the diagonal: aspect up to ~3
MIN_VOLUME_CHANGE = 0.01  # of the solid's volume: smaller changes are degenerate
MIN_FACE_AREA = 1e-3 * DIAG**2  # smaller faces are slivers no one sketches on
TRIES = 25  # operation draws before giving up on a solid


class Stage:
    """A solid of a sequence, with what drawing operations on it needs (computed once).

    Attributes:
        solid: the solid (mm, world frame).
        volume: its volume (mm^3).
    """

    def __init__(self, solid: cq.Solid, volume: float | None = None):
        """`volume`: the solid's, when known (an operation's result carries it)."""
        self.solid = solid
        self.volume = float(solid.Volume() if volume is None else volume)
        self._faces: list[PlanarFace] | None = None

    @property
    def faces(self) -> list[PlanarFace]:
        """Planar faces of at least MIN_FACE_AREA (found on first use: a last
        operation's result never needs them)."""
        if self._faces is None:
            self._faces = [
                PlanarFace(f, n)
                for f, n, _ in planar_faces(self.solid)
                if f.Area() >= MIN_FACE_AREA
            ]
        return self._faces


@dataclass
class Sequence:
    """A sampled protocol and its stages: stages[0] is the box, stages[i] the solid
    after operation i."""

    protocol: Protocol
    stages: list[Stage]

    @property
    def solids(self) -> list[cq.Solid]:
        return [s.solid for s in self.stages]


def random_box(rng: np.random.Generator) -> Box:
    """A box with random aspect and a diagonal of DIAG mm."""
    s = rng.uniform(*BOX_SIDES, 3)
    s *= DIAG / np.linalg.norm(s)
    return Box(tuple(float(round(x, 3)) for x in s))


def draw_type(
    rng: np.random.Generator, weights: dict[OperatorType, int] = LAST_OP_WEIGHTS
) -> OperatorType:
    """An operator type with the given relative frequencies (1:1:4:2 by default); types
    of weight 0 take no part in the draw."""
    types = [t for t in weights if weights[t] > 0]
    w = np.array([weights[t] for t in types], float)
    return types[rng.choice(len(types), p=w / w.sum())]


@dataclass
class Drawn:
    """An operation drawn on a stage: the operation, its base face f on the stage's
    solid, and the stage it produces."""

    op: Operation
    face: PlanarFace
    result: Stage


def is_regular(rng: np.random.Generator, regular_share: float) -> bool:
    """Whether the next operation is regular: with probability `regular_share`, and
    without drawing from `rng` when it is 0 (the data stays what it was before the
    option)."""
    return regular_share > 0 and bool(rng.random() < regular_share)


def sample_operation(
    rng: np.random.Generator,
    stage: Stage,
    kind: OperatorType,
    regular_share: float = 0.0,
    keep: Callable[[Operation], bool] | None = None,
    round_share: float = 0.0,
) -> Drawn | None:
    """An operation of type `kind` on a random planar face that builds and changes the
    volume by at least MIN_VOLUME_CHANGE; None when TRIES draws all fail (this solid
    admits no such operation). It is regular (datagen/regular.py) with probability
    `regular_share`, decided once, so that retries keep the share. `keep`: a condition
    the operation must meet too (datagen/curved.py's straight additions), checked
    before its Boolean; a draw that fails it counts as one of the TRIES. A bevel is a
    round across an edge (datagen/rounds.py) with probability `round_share`, decided
    once as well (and not drawn at all when 0)."""
    if not stage.faces:
        return None
    samplers = REGULAR_SAMPLERS if is_regular(rng, regular_share) else SAMPLERS
    faces = stage.faces
    if kind is OperatorType.BEVEL and is_regular(rng, round_share):
        samplers = {**samplers, OperatorType.BEVEL: sample_round}
        faces = round_faces(rng, faces)
    least = MIN_VOLUME_CHANGE * stage.volume
    for _ in range(TRIES):
        face = faces[int(rng.integers(len(faces)))]
        op = samplers[kind](rng, stage.solid, face)
        if op is None or change_bound(op, face) < least or (keep and not keep(op)):
            continue  # rejected before paying for the Boolean
        try:  # f is the face op.face was drawn from: not resolved again
            out = operation_result(stage.solid, op, face.face)
        except OperationError:
            continue
        after = Stage(out.solid, out.volume)
        if abs(after.volume - stage.volume) >= least:
            return Drawn(op, face, after)
    return None


def sample_sequence(
    rng: np.random.Generator,
    length: int,
    last: OperatorType | None = None,
    regular_share: float = 0.0,
) -> Sequence:
    """A protocol of `length` (0 to 4) operations on a random box.

    The last operation has type `last`, or one drawn 1:1:4:2 when None; it is drawn
    once, before any retry, so that types which fail more often keep their share.
    Earlier operations are of any type. A sequence that gets stuck starts over from a
    new box. Each operation is regular with probability `regular_share`.
    """
    if length == 0:
        box = random_box(rng)
        return Sequence(Protocol(box), [Stage(make_box(box))])
    last = last or draw_type(rng)
    while True:
        box = random_box(rng)
        stages = [Stage(make_box(box))]
        ops: list[Operation] = []
        for i in range(length):
            kind = last if i == length - 1 else draw_type(rng, EARLIER_OP_WEIGHTS)
            got = sample_operation(rng, stages[-1], kind, regular_share)
            if got is None:
                break
            ops.append(got.op)
            stages.append(got.result)
        if len(ops) == length:
            return Sequence(Protocol(box, tuple(ops)), stages)
