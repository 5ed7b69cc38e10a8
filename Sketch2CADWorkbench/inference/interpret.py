# SPDX-License-Identifier: LGPL-2.1-or-later
"""The interpret pipeline: strokes and camera -> maps -> networks -> fitting -> operation.

    interpret(solid, strokes, view, predictor) -> Interpretation

The strokes are pixel polylines in the designer's view. The context camera frames
twice the sketch's bounding box (paper, Sec. 4); the context solid is rendered there
to D, N and face IDs; the predictor classifies the operator and segments the base
face F and the curves C; fitting turns those into an operation; the operation is
applied to a copy of the solid. Any failure raises InterpretError with the reason,
and the caller's solid is untouched.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Protocol as TypingProtocol

import cadquery as cq
import numpy as np
from scipy.optimize import minimize_scalar

from ..brep.faces import (
    OperationError,
    ResolvedFace,
    face_at,
    face_kinds,
    model_scale,
    plane_normals,
    resolve_face,
)
from ..brep.operators import apply_operation
from ..brep.protocol import (
    AddSubPrism,
    Extrude,
    FaceRef,
    Mode,
    Operation,
    OperatorType,
    Sweep,
    per_operator,
)
from ..brep.symmetry import mid_plane, reflect
from ..render.camera import OrthoCamera
from ..render.frustum import context_camera
from ..render.maps import ContextMaps, MapRenderer
from ..render.strokes import rasterize
from ..sketch.labels import CLASSES, CURVE_THRESHOLDS

# What one sketch step may hold: a person draws tens of strokes for an operation.
MAX_STROKES, MAX_POINTS = 200, 20000
MIN_SPAN_PX = 3.0  # strokes spanning less are a dot, not edges
# A reading is flagged as doubtful when a measure of SketchFit passes its threshold
# here (context pixels): the strokes' mean distance to the reading's own sketch, or the
# sketch's to the strokes (their mean, misfit_px, then passes neither): each the 99.5%
# quantile of held-out level-1 sketches, rounded up (datagen seed 30001, 7.61 and 7.67 px
# with stop 21's operator search; scripts/misfit_threshold.py). On another seed it flags
# 1.0% of 400 such sketches (docs/NOTES.md, stop 21).
DOUBT = {"strokes_off_px": 7.7, "sketch_off_px": 7.7}
# A sample of the strokes or of the sketch farther than this (context pixels) from the
# other is not explained by it.
EXPLAINED_PX = 4.0
# A result whose volume (and bounding box, in model diagonals) differs from the model's by
# less than this share is the model unchanged: such a step is refused.
SAME_VOLUME = 1e-6
# A face whose outward normal is within this cosine of edge-on, or turned away from the
# view, is one the user cannot see from it.
FACING_COS = 0.05
# A primitive whose base centre lies farther than this (context pixels, in depth) behind
# the surface the view shows there stands where the designer could not see it: the
# outline drawn around a post's top back-projects just as well onto the plate far behind
# it, along the view rays (examples/sessions/lamp.json, step 3). Such a reading ranks
# with those on hidden faces. A few pixels: a centre on f sees f itself (depth equal).
BEHIND_PX = 4.0
from .alternative import Alternative, explained, one_way_scores, seen_distances, the_meant
from .fitting.addsub import PrismFit, prism_fit
from .fitting.base_face import face_under_stroke, rank_base_faces
from .fitting.bevel import bevel_fit
from .fitting.common import FitError, classify_strokes, resample, sample_map
from .fitting.extrude import fit_extrude, fit_extrude_by_ends
from .fitting.primitive import ON_FACE_FRACTION, base_centre, base_share, other_option_fits
from .fitting.regularize import Snap, StrokeFit, hand_tolerance, regularize_operation
from .fitting.stroke_roles import PRISM_CHORD_TOLERANCES, stroke_roles
from .fitting.surface import face_frame
from .fitting.sweep import SweepFit, sweep_fit
from .fitting.verify import DrawnStrokes, mean_distance, reading_score, sketch_distances
from .options import InterpretOptions

# Base faces fitted at most, in the order of the face map's counting; a fit whose own
# sketch lies within GOOD_FIT_PX (mean, both ways) of the strokes ends the search.
BASE_FACE_TRIES = 4
# The operators whose base face may be a cylinder's or cone's side (fitting/surface.py;
# an extrusion of one changes its radius: fitting/extrude.py).
ON_CURVED_FACES = (OperatorType.EXTRUDE, OperatorType.ADDSUB, OperatorType.SWEEP)
GOOD_FIT_PX = 3.0
# Operators, like faces, are one search: the most probable operator that fits is read
# first, and when its reading lies over GOOD_FIT_PX from the strokes the others are read
# too, in the order of their probability p. Another operator's reading replaces it only
# when the classifier gives it at least OVERRULE_PROB and it reads the strokes within
# GOOD_FIT_PX (a clear fit, not the better of two poor ones: thirty random short strokes
# fit some prism to 3-5 px), and then only if its score, its reprojection error plus
# PRIOR_PX per decade of doubt (-log10 p), is the lower. When the reading it would replace
# is doubtful (SketchFit), a score within RESCUE_SCORE_PX is enough: a fit just past
# GOOD_FIT_PX that the classifier finds likely (a level-3 extrusion at 3.4 px, p 0.5,
# over a sweep at 53 px), where the prisms thirty random strokes fit score 4.4-8.8. A
# triangle whose edges are all drawn is a prism however sure the classifier is of a sweep
# (p 0.003 against 0.996). PRIOR_PX is not tuned: a decade of doubt weighs about a
# level-1 hand's error (median misfit 1.4 px); figures in docs/NOTES.md (stops 21, 22).
PRIOR_PX = 1.0
OVERRULE_PROB = 1e-3
RESCUE_SCORE_PX = GOOD_FIT_PX + PRIOR_PX  # a good fit with one decade of doubt
# The operators the designer's Boolean choice (InterpretOptions.option) applies to: with
# one chosen, only these are read.
TAKE_A_BOOLEAN = (OperatorType.ADDSUB, OperatorType.SWEEP)
# An extrusion's d is also searched by the score its readings are ranked by, around the
# line search's readings (their range widened by SCORE_SEARCH_SPAN of d or SCORE_SEARCH_PX,
# whichever is more) in at most SCORE_SEARCH_STEPS scorings: held-out extrusions read so
# beside the line search's, level 1 88.5 -> 91.7% recovered, level 3 66.7 -> 67.3% (mean
# volume IoU .943 -> .952); 20 steps read the same as 10 (docs/NOTES.md, stop 31).
SCORE_SEARCH_SPAN = 0.1
SCORE_SEARCH_PX = 8.0
SCORE_SEARCH_STEPS = 10
# Strokes tried as the bevel's profile l, in the order of C's votes.
BEVEL_READINGS = 2
# Of a prism's readings of the stroke roles, those whose unrefined sketch lies within
# this factor of the closest one's distance from the strokes are refined: readings
# farther apart refined to within 0.1 px of each other on held-out level 1 (docs/NOTES.md,
# stop 26).
REFINE_WITHIN = 1.5


class InterpretError(ValueError):
    """The sketch could not be turned into an operation; the message is for the user."""


class Predictor(TypingProtocol):
    """The networks: operator probabilities, then the operator's F and C maps."""

    def classify(self, inputs: np.ndarray) -> np.ndarray:
        """(5, H, W) inputs S, D, N -> (4,) probabilities in OperatorType order."""

    def segment(self, inputs: np.ndarray, op_type: OperatorType) -> tuple[np.ndarray, np.ndarray]:
        """(5, H, W) inputs -> F (H, W) base-face probability and C (H, W) curve map."""


@dataclass(frozen=True)
class SketchFit:
    """How well a reading's own sketch (the lines the data generator draws for it)
    explains the strokes, and the strokes it: scribbles are otherwise read as something.

    A reading is doubtful when any measure passes its threshold in DOUBT (above it; the
    confidence below it), each set on real held-out level-1 sketches
    (scripts/misfit_threshold.py, docs/NOTES.md). The measures DOUBT leaves out were
    tried too: they told scribbles from real sketches less well.
    """

    misfit_px: float  # symmetric mean distance between strokes and sketch
    strokes_off_px: float  # mean distance of the strokes' samples to the sketch
    sketch_off_px: float  # mean distance of the sketch's samples to the strokes
    strokes_unexplained: float  # share of stroke samples over EXPLAINED_PX from the sketch
    sketch_unexplained: float  # share of sketch samples over EXPLAINED_PX from the strokes
    confidence: float  # the classifier's probability of the operator read

    MEASURES = (
        "misfit_px",
        "strokes_off_px",
        "sketch_off_px",
        "strokes_unexplained",
        "sketch_unexplained",
        "confidence",
    )

    @staticmethod
    def of(
        solid: cq.Shape,
        op: Operation,
        camera: OrthoCamera,
        strokes: list[np.ndarray],
        confidence: float,
    ) -> "SketchFit":
        return SketchFit.of_distances(*sketch_distances(solid, op, camera, strokes)[:2], confidence)

    @staticmethod
    def of_distances(
        to_sketch: np.ndarray, to_strokes: np.ndarray, confidence: float
    ) -> "SketchFit":
        """From `verify.sketch_distances`' first two arrays."""
        return SketchFit(
            mean_distance((to_sketch, to_strokes)),
            float(to_sketch.mean()),
            float(to_strokes.mean()),
            float(np.mean(to_sketch > EXPLAINED_PX)),
            float(np.mean(to_strokes > EXPLAINED_PX)),
            float(confidence),
        )

    def to_dict(self) -> dict[str, float]:
        return {k: getattr(self, k) for k in self.MEASURES}

    def passed(self) -> list[str]:
        """The measures past their DOUBT thresholds."""
        return [
            k
            for k, limit in DOUBT.items()
            if (getattr(self, k) < limit if k == "confidence" else getattr(self, k) > limit)
        ]

    @property
    def doubtful(self) -> bool:
        return bool(self.passed())


@dataclass
class Interpretation:
    """What a sketch step was read as, and the resulting solid."""

    operations: tuple[Operation, ...]  # the operation, then its mirror image if asked
    solid: cq.Solid
    op_type: OperatorType
    probabilities: dict[str, float]
    base_face: int
    stroke_labels: list[int]
    camera: OrthoCamera  # the context camera (maps' pixels)
    # ms per stage: render, networks, fitting, brep (every Boolean built: the readings'
    # results, which fitting builds to refuse one that fails or changes nothing, and the
    # step's mirror image or regularized rebuild) and total
    timings_ms: dict[str, float] = field(default_factory=dict)
    # The other Boolean's reading when it explains the same strokes too (a boss on f and
    # a hole into f draw the same lines in a parallel view, paper Fig. 5b): alternative.py
    alternative: Alternative | None = None
    # How well the operation's own sketch and the strokes explain each other.
    fit: SketchFit | None = None
    # The snaps regularization applied, in order (InterpretOptions.skip_snaps undoes one).
    snaps: tuple[Snap, ...] = ()
    # Why the snaps found were not applied (the snapped shape does not build); "" if none.
    unsnapped: str = ""

    @property
    def other_option(self) -> Mode | None:
        """The Boolean that reads the strokes too (the alternative's); None when none does."""
        return self.alternative.option if self.alternative else None

    @property
    def misfit_px(self) -> float:
        """How far (px, symmetric mean) the operation's own sketch lies from the strokes."""
        return self.fit.misfit_px if self.fit else 0.0

    @property
    def doubtful(self) -> bool:
        """The strokes do not look like this operation (SketchFit's DOUBT): say so."""
        return self.fit is not None and self.fit.doubtful

    def doubt(self) -> str:
        """The warning for a doubtful reading ("" when it is not)."""
        if not self.doubtful:
            return ""
        f, what = self.fit, self.op_type.value
        why = {
            "misfit_px": f"its own sketch lies {f.misfit_px:.1f} px from them",
            "strokes_off_px": f"the strokes lie {f.strokes_off_px:.1f} px from its sketch",
            "sketch_off_px": f"its sketch lies {f.sketch_off_px:.1f} px from the strokes",
            "strokes_unexplained": f"{f.strokes_unexplained:.0%} of the strokes are not "
            "lines of it",
            "sketch_unexplained": f"{f.sketch_unexplained:.0%} of its lines were not drawn",
            "confidence": f"the networks are {1 - f.confidence:.0%} unsure",
        }
        return (
            f"the strokes do not look much like this {what}: "
            + "; ".join(why[k] for k in f.passed())
            + " (beyond 99.5% of held-out synthetic sketches); check it, or clear and "
            "draw again"
        )


@dataclass
class Context:
    """The rendered context of a sketch: camera, strokes in its pixels, maps, net inputs."""

    camera: OrthoCamera
    strokes: list[np.ndarray]
    maps: ContextMaps
    inputs: np.ndarray
    # `sketch_distances` by (solid, operation): a face's fit scores its readings, and the
    # one it keeps is scored again among the faces' readings
    scores: dict[tuple[cq.Shape, Operation], tuple[np.ndarray, np.ndarray]] = field(
        default_factory=dict, repr=False, compare=False
    )
    # base faces resolved by (solid, reference): every reading on one planar face names
    # it alike, and each is scored and built
    faces: dict[tuple[cq.Shape, FaceRef], ResolvedFace] = field(
        default_factory=dict, repr=False, compare=False
    )
    # seconds spent building readings' results (`_builds_a_change`): B-rep work done while
    # reading, timed as the B-rep stage
    build_s: float = field(default=0.0, compare=False)
    # renders what a reading's result lets the view see (`_weigh_the_other_boolean`);
    # None: readings are weighed by every line only
    renderer: MapRenderer | None = field(default=None, repr=False, compare=False)

    @cached_property
    def drawn(self) -> DrawnStrokes:
        """The strokes as every reading of them is scored against them."""
        return DrawnStrokes(self.strokes, (self.camera.height, self.camera.width))

    def resolved(self, solid: cq.Shape, ref: FaceRef) -> ResolvedFace:
        """`resolve_face` of ref on `solid`, once for each (OperationError as it)."""
        if (solid, ref) not in self.faces:
            self.faces[solid, ref] = resolve_face(solid, ref)
        return self.faces[solid, ref]

    def sketch_distances(
        self, solid: cq.Shape, op: Operation
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """`verify.sketch_distances` of op on `solid` and the strokes, once for each."""
        if (solid, op) not in self.scores:
            self.scores[solid, op] = sketch_distances(
                solid, op, self.camera, self.drawn, face=self.resolved(solid, op.face)
            )
        return self.scores[solid, op]


def to_context(
    solid: cq.Shape,
    strokes: list[np.ndarray],
    view: OrthoCamera,
    renderer: MapRenderer,
    size: int = 256,
) -> Context:
    """Frame, transform and rasterise the sketch and render the context maps."""
    if not strokes or all(len(s) < 2 for s in strokes):
        raise InterpretError("there are no strokes to interpret")
    pts = np.concatenate([np.asarray(s, float) for s in strokes])
    cam = context_camera(view, pts, size=size)
    ctx = [cam.project(view.unproject(np.asarray(s, float)))[0] for s in strokes if len(s) >= 2]
    maps = renderer.render(solid, cam)
    sketch = rasterize(ctx, cam.width, cam.height)
    inputs = np.concatenate([sketch[None], maps.depth[None], maps.normal]).astype(np.float32)
    return Context(cam, ctx, maps, inputs, renderer=renderer)


Fit = tuple[Operation, int, list[int]]  # an operation, the face it stands on, stroke labels


@dataclass
class Reading:
    """One base face's fitted operation: how far its own sketch lies from the strokes,
    whether it is hidden from the sketch view (its face, or a primitive's base behind the
    model), and (once built) the result."""

    distances: tuple[np.ndarray, np.ndarray, np.ndarray]  # `verify.sketch_distances`
    op: Operation
    index: int
    labels: list[int]
    hidden: bool
    result: cq.Solid | None = None
    refused: str = ""  # why it cannot be the step: its Boolean fails or changes nothing
    # read with the other Boolean because none with the first built: no flip back to it
    flip_refused: bool = False
    # `distances` of the lines its result lets the view see, once weighed against its
    # other Boolean (`_weigh_the_other_boolean`); None until then
    seen: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
    # its other Boolean's reading when that explains the strokes too (alternative.py)
    alternative: "Reading | None" = None

    @property
    def explained(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """`distances` or `seen`, whichever explains the strokes better
        (`alternative.explained`)."""
        return explained(self.distances, self.seen)

    @property
    def error(self) -> float:
        """Symmetric mean distance (pixels) of `explained`, `verify.mean_distance`."""
        return mean_distance(self.explained)

    @property
    def score(self) -> float:
        """What readings are ranked by (pixels), `verify.reading_score` of `explained`."""
        return reading_score(self.explained)

    @property
    def doubtful(self) -> bool:
        """Its own sketch and the strokes lie apart past DOUBT (SketchFit)."""
        return SketchFit.of_distances(*self.explained[:2], 1.0).doubtful


def leaves_unchanged(before: cq.Shape, after: cq.Shape) -> bool:
    """Whether a step's result is the model it started from: the same volume (within
    SAME_VOLUME of it), bounding box and number of faces (a primitive wholly in the air,
    cut away, or wholly inside the model, added)."""
    vb = float(before.Volume())
    if abs(float(after.Volume()) - vb) > SAME_VOLUME * vb:
        return False
    tol = SAME_VOLUME * model_scale(before)
    a, b = before.BoundingBox(), after.BoundingBox()
    box = lambda bb: (bb.xmin, bb.ymin, bb.zmin, bb.xmax, bb.ymax, bb.zmax)  # noqa: E731
    return all(abs(x - y) <= tol for x, y in zip(box(a), box(b))) and len(before.Faces()) == len(
        after.Faces()
    )


def _builds_a_change(solid: cq.Shape, reading: Reading, ctx: Context) -> bool:
    """Build the reading's operation; keep the result, or say why it cannot be the step
    (the time goes to ctx.build_s)."""
    if reading.result is None and not reading.refused:
        start = time.perf_counter()
        try:
            op = reading.op
            # a planar f is held (resolved while the reading was scored), a curved one
            # resolved where the step stands
            held = None if op.face.surface.curved else ctx.resolved(solid, op.face).face
            result = apply_operation(solid, op, held)
        except OperationError as e:
            reading.refused = str(e)
        else:
            if leaves_unchanged(solid, result):
                reading.refused = (
                    f"the {reading.op.type.value} it reads would leave the model "
                    "as it is (it adds or removes nothing there); draw it over "
                    "the face it stands on"
                )
            else:
                reading.result = result
        finally:
            ctx.build_s += time.perf_counter() - start
    return reading.result is not None


def snap_or_keep(
    solid: cq.Shape,
    op: Operation,
    face: cq.Face,
    distances: Callable[[Operation], tuple[np.ndarray, ...]],
    context: OrthoCamera,
    view: OrthoCamera,
    options: InterpretOptions,
) -> tuple[Operation, tuple[Snap, ...], cq.Solid | None, str]:
    """A fitted operation regularized within the hand's tolerance (`hand_tolerance` of
    its misfit) and built: the operation, its snaps, its result and "". When nothing
    snaps, or the snapped operation does not build (a snapped sweep OCCT calls invalid):
    `op` itself, no snaps, None (the caller holds its result) and why not, if it did not
    build. Snapping never costs a reading that builds.

    `distances(op)`: an operation's `sketch_distances` to the strokes in pixels of the
    `context` camera it was fitted in. Their mean is op's misfit, and snapping asks it of
    the operations it moves (`StrokeFit`, a clear fit within GOOD_FIT_PX; one whose sketch
    cannot be drawn lies infinitely far): a target beyond the tolerance, or a round
    length, is taken where the strokes still fit the operation moved there."""

    def distance(moved: Operation) -> float:
        try:
            return mean_distance(distances(moved))
        except OperationError:
            return float("inf")

    tol = hand_tolerance(options.snap_px, mean_distance(distances(op)), context, view)
    reg = regularize_operation(
        solid,
        op,
        face,
        view,
        options.snap_step,
        tol,
        options.skip_snaps,
        StrokeFit(distance, GOOD_FIT_PX),
    )
    if not reg.snaps:
        return op, (), None, ""
    try:
        return reg.operation, reg.snaps, apply_operation(solid, reg.operation), ""
    except OperationError as e:
        return op, (), None, f"snapped, it would not build ({e}), so it stays as drawn"


def _snapped(
    solid: cq.Shape, reading: Reading, ctx: Context, view: OrthoCamera, options: InterpretOptions
) -> tuple[Operation, tuple[Snap, ...], cq.Solid, str]:
    """`snap_or_keep` for a reading, its result the reading's own when it is kept (the
    rebuild goes to ctx.build_s)."""
    start = time.perf_counter()
    op, snaps, result, why = snap_or_keep(
        solid,
        reading.op,
        face_at(solid, reading.index),
        lambda moved: ctx.sketch_distances(solid, moved),
        ctx.camera,
        view,
        options,
    )
    ctx.build_s += time.perf_counter() - start
    return op, snaps, reading.result if result is None else result, why


def hidden_faces(solid: cq.Shape, camera: OrthoCamera) -> set[int]:
    """Planar faces the user cannot see from the view: turned away from it, or seen
    within FACING_COS of edge-on."""
    d = np.asarray(camera.basis()[2], float)
    return {i for i, n in plane_normals(solid).items() if float(n @ d) > -FACING_COS}


def stands_behind_the_model(op: Operation, ctx: Context) -> bool:
    """Whether a prism's or sweep's base centre lies behind the model's surface in the
    view (BEHIND_PX), where the designer could not have drawn it."""
    if not isinstance(op, (AddSubPrism, Sweep)) or ctx.maps.view_depth is None:
        return False
    pixel, depth = ctx.camera.project(base_centre(op)[None])
    seen = float(sample_map(ctx.maps.view_depth, pixel)[0])  # +inf over the background
    return float(depth[0]) > seen + BEHIND_PX * ctx.camera.pixel_size


def candidate_faces(
    solid: cq.Shape, face_prob: np.ndarray, ctx: Context, hidden: set[int], curved: bool = False
) -> list[int]:
    """The base faces to fit, best first: the network's BASE_FACE_TRIES by counting, then
    the planar faces most of a stroke lies on (an outline is drawn on its base face, so
    a face F missed is still tried), faces `hidden` from the view (`hidden_faces`) after
    all others. `curved`: cylinders' and cones' sides count too (`rank_base_faces`)."""
    ranked = rank_base_faces(face_prob, ctx.maps.face_id, solid, curved)[:BASE_FACE_TRIES]
    kinds = face_kinds(solid)
    for s in ctx.strokes:
        under = face_under_stroke(s, ctx.maps.face_id)
        if under is not None and under not in ranked and kinds[under] == "PLANE":
            ranked.append(under)
    return sorted(ranked, key=lambda i: i in hidden)


def read_operation(
    solid: cq.Shape,
    op_type: OperatorType,
    face_prob: np.ndarray,
    curve: np.ndarray,
    ctx: Context,
    options: InterpretOptions,
) -> Reading:
    """Stage three: the base face by counting, then the operator's fitting, then the
    operation built.

    The paper takes the planar face with the most F > 0.5 pixels. A network unsure of
    F often ranks the right face second, so when that face's fit fails or leaves its
    own sketch more than GOOD_FIT_PX from the strokes, the next faces are fitted too
    (`candidate_faces`): of the readings that build and change the model, one on a face
    the user sees wins over one on a hidden face or standing behind the model (BEHIND_PX),
    then the one whose sketch reprojects best (`verify.reading_score`). A reading that
    changes nothing (a hole cut into the air above a lower face) is never the step; when
    the best one builds nothing, its other Boolean (`_with_the_other_boolean`) competes
    with the others by the same ranking.

    A face or a reading whose own sketch cannot be drawn for its score (an outline that
    leaves a curved face: OperationError) is passed over like one that does not fit.

    Returns:
        The reading, with its result built (without any mirror image).
    Raises:
        FitError: the strokes do not fit the operator on this model (the reason given
            for the best face), or every fitted reading fails to build or changes nothing.
        OperationError: no reading could be scored, the first one's reason.
    """
    hidden = hidden_faces(solid, ctx.camera)
    order = candidate_faces(solid, face_prob, ctx, hidden, op_type in ON_CURVED_FACES)
    if not order:
        raise FitError(
            "no face of the model was recognised under the sketch; draw on a visible face"
        )
    readings, first = [], None
    for index in order:
        try:
            fits = _fit_on_face(solid, op_type, index, curve, ctx, options)
        except (FitError, OperationError) as e:
            first = first or e
            continue
        for fit in fits:
            try:
                reading = _reading(solid, fit, ctx, hidden)
            except OperationError as e:
                first = first or e
                continue
            readings.append(reading)
            if (
                reading.error <= GOOD_FIT_PX
                and not reading.hidden
                and _builds_a_change(solid, reading, ctx)
            ):
                return _weigh_the_other_boolean(solid, op_type, reading, curve, ctx, options)
    readings.sort(key=lambda r: (r.hidden, r.score))
    if readings and not _builds_a_change(solid, readings[0], ctx):
        # the best reading's other Boolean draws its lines too (paper Fig. 5b): it competes
        # by its score with the rest, before a reading that explains the strokes worse
        readings = sorted(
            readings
            + _with_the_other_boolean(solid, op_type, readings, curve, ctx, options, hidden),
            key=lambda r: (r.hidden, r.score),
        )
    for reading in readings:
        if _builds_a_change(solid, reading, ctx):
            return _weigh_the_other_boolean(solid, op_type, reading, curve, ctx, options)
    if readings:
        raise FitError(readings[0].refused)
    raise first


def _weigh_the_other_boolean(
    solid: cq.Shape,
    op_type: OperatorType,
    reading: Reading,
    curve: np.ndarray,
    ctx: Context,
    options: InterpretOptions,
) -> Reading:
    """Of a primitive's built reading and the one of its other Boolean on its face, the
    one the strokes mean, with the other as its `alternative` when that is offered
    (alternative.py: each weighed by its lines drawn all or only where its result lets
    the view see them, and where each would stand on f). Weighed only when the designer chose no Boolean, the reading is
    not already the other Boolean of one that did not build, and its far outline stands
    on f (`other_option_fits`: the other one's base must, to be read); and against an
    other reading that builds a change and is not hidden where the reading is not."""
    if (
        ctx.renderer is None
        or options.option is not None
        or op_type not in TAKE_A_BOOLEAN
        or reading.flip_refused
        or not other_option_fits(face_at(solid, reading.index), ctx.camera, reading.op)
    ):
        return reading
    hidden = hidden_faces(solid, ctx.camera)
    others = _with_the_other_boolean(solid, op_type, [reading], curve, ctx, options, hidden)
    other = next(
        (r for r in others if r.hidden <= reading.hidden and _builds_a_change(solid, r, ctx)),
        None,
    )
    if other is None:
        return reading
    for r in (reading, other):
        face = ctx.resolved(solid, r.op.face)
        r.seen = seen_distances(solid, r.op, r.result, ctx.camera, ctx.drawn, ctx.renderer, face)
    face = face_at(solid, reading.index)
    share = [base_share(face, ctx.camera, r.op) for r in (reading, other)]
    scores = one_way_scores((reading.distances, reading.seen), (other.distances, other.seen))
    flip, offered = the_meant(*scores, share[1] >= min(share[0], ON_FACE_FRACTION))
    taken, left = (other, reading) if flip else (reading, other)
    taken.alternative = left if offered else None
    return taken


def _reading(solid: cq.Shape, fit: Fit, ctx: Context, hidden: set[int]) -> Reading:
    """A fit scored against the strokes; hidden when its face is (`hidden_faces`) or it
    stands behind the model."""
    op, used, labels = fit
    return Reading(
        ctx.sketch_distances(solid, op),
        op,
        used,
        labels,
        used in hidden or stands_behind_the_model(op, ctx),
    )


def _with_the_other_boolean(
    solid: cq.Shape,
    op_type: OperatorType,
    refused: list[Reading],
    curve: np.ndarray,
    ctx: Context,
    options: InterpretOptions,
    hidden: set[int],
) -> list[Reading]:
    """When the best reading of a primitive builds no change, it fitted again with the
    other Boolean on its face (the designer chose none), the closest first: a boss read
    as the hole its lines also draw (paper Fig. 5b) may cut the model in two, or cut
    only air, where the boss builds."""
    if (
        options.option is not None
        or op_type not in TAKE_A_BOOLEAN
        or not refused
        or refused[0].op.mode.flipped is None
    ):
        return []
    best = refused[0]
    other = best.op.mode.flipped
    try:
        fits = _fit_on_face(solid, op_type, best.index, curve, ctx, replace(options, option=other))
    except (FitError, OperationError):
        return []
    # a primitive's fits were scored by `_scored_readings`, which drops any that cannot be
    # drawn: no OperationError to guard against here
    readings = sorted((_reading(solid, fit, ctx, hidden) for fit in fits), key=lambda r: r.score)
    for reading in readings:
        reading.flip_refused = True
    return readings


def _fit_on_face(
    solid: cq.Shape,
    op_type: OperatorType,
    index: int,
    curve: np.ndarray,
    ctx: Context,
    options: InterpretOptions,
) -> list[Fit]:
    """The operator's fittings on base face `index`, the likeliest first: one, or for a
    primitive one per reading of the strokes' roles (`_fit_by_roles`)."""
    return _FIT_ON_FACE[op_type](solid, index, curve, ctx, options)


def _fit_extrude_on_face(
    solid: cq.Shape, index: int, curve: np.ndarray, ctx: Context, options: InterpretOptions
) -> list[Fit]:
    """The extrusion on face `index`, its offset and side edges as C labels them (an
    extrusion's sign is read from the strokes: `options` has nothing for it). On a
    polygon, d read from the strokes' ends, on a cylinder's or cone's side from the ends
    of its lines and its rims' loops (`fit_extrude_by_ends`, the likeliest d under the
    hand's noise), refused where the line search's would be (the moved outline
    MAX_MISMATCH_PX from the strokes). Elsewhere (a disk, an outline with arcs), or when
    no stroke pairs with a curve, or that reading is refused, the paper's line search:
    d read with the strokes' ends (`fit_extrude`'s END_WEIGHT) and d read by closeness
    alone when that differs, the one that explains the strokes better (`reading_score`)
    first, the other built if that one is refused (a top pushed down past a hole's rim,
    say, falls apart)."""
    face = face_at(solid, index)
    strokes, cam = ctx.strokes, ctx.camera
    labels = classify_strokes(strokes, curve, CURVE_THRESHOLDS[OperatorType.EXTRUDE][:1])
    offset, sides = ([s for s, l in zip(strokes, labels) if l == part] for part in (1, 0))
    by_ends = fit_extrude_by_ends(solid, face, cam, offset, sides)
    if by_ends is not None:
        # refused as the line search's reading would be: the outline too far off, by C's
        # parts or, as the line search falls back below, with every stroke serving both
        for parts in ((offset, sides), (strokes, strokes)):
            try:
                return [(fit_extrude(solid, face, cam, *parts, at=by_ends.d), index, labels)]
            except FitError:
                pass
    ops = []
    for ends in ({}, {"end_weight": 0.0}):
        try:
            op = fit_extrude(solid, face, cam, offset, sides, **ends)
        except FitError:
            # C may call a side edge an offset edge or back. The line search scores the
            # moved edges' distance to the strokes, which strokes of the other part
            # rarely mislead, so every stroke may serve both parts.
            op = fit_extrude(solid, face, cam, strokes, strokes, **ends)
        if op not in ops:
            ops.append(op)

    def score(op: Operation) -> float:
        try:
            return reading_score(ctx.sketch_distances(solid, op))
        except OperationError:
            return np.inf

    best = _extrusion_by_score(ops, score, cam.pixel_size, 1e-6 * model_scale(solid))
    if best not in ops:
        ops.append(best)
    return [(op, index, labels) for op in sorted(ops, key=score)]


def _extrusion_by_score(
    ops: list[Extrude], score: Callable[[Operation], float], pixel: float, least: float
) -> Extrude:
    """The extrusion whose d minimises `score` (`verify.reading_score`, the score readings
    are ranked by, of which the line search's terms are cheaper stand-ins) within the
    range of the line search's readings `ops` widened by SCORE_SEARCH_SPAN of their d or
    SCORE_SEARCH_PX, whichever is more, to a quarter pixel (`pixel`: mm per pixel); an
    offset under `least` (mm) is no operation."""
    ds = [op.d for op in ops]
    span = max(
        max(ds) - min(ds), SCORE_SEARCH_SPAN * max(abs(d) for d in ds), SCORE_SEARCH_PX * pixel
    )
    found = minimize_scalar(
        lambda d: score(replace(ops[0], d=float(d))) if abs(d) >= least else np.inf,
        bounds=(min(ds) - span, max(ds) + span),
        method="bounded",
        options={"xatol": 0.25 * pixel, "maxiter": SCORE_SEARCH_STEPS},
    )
    return replace(ops[0], d=float(found.x))


def _fit_prism_on_face(
    solid: cq.Shape, index: int, curve: np.ndarray, ctx: Context, options: InterpretOptions
) -> list[Fit]:
    """The add/sub prism on face `index` (`_fit_by_roles`)."""
    return _fit_by_roles(prism_fit, OperatorType.ADDSUB, solid, index, curve, ctx, options)


def _fit_sweep_on_face(
    solid: cq.Shape, index: int, curve: np.ndarray, ctx: Context, options: InterpretOptions
) -> list[Fit]:
    """The sweep on face `index` (`_fit_by_roles`)."""
    return _fit_by_roles(sweep_fit, OperatorType.SWEEP, solid, index, curve, ctx, options)


def _fit_by_roles(
    fit: Callable[..., PrismFit | SweepFit],
    op_type: OperatorType,
    solid: cq.Shape,
    index: int,
    curve: np.ndarray,
    ctx: Context,
    options: InterpretOptions,
) -> list[Fit]:
    """A primitive (prism or sweep) `fit` on face `index` by the stroke roles C gives and
    by those read from the strokes' geometry, the one whose own sketch lies closest to
    the strokes first. All are kept: a thin slot seen nearly along f's normal also
    reads, a little closer, as a tall post on its end, which a chosen subtract refuses
    (it cuts nothing), and then the slot's own roles are the step."""
    face = face_at(solid, index)
    strokes, cam = ctx.strokes, ctx.camera
    labels = classify_strokes(strokes, curve, CURVE_THRESHOLDS[op_type])
    readings = [labels]
    prism = op_type is OperatorType.ADDSUB
    # a prism drawn with all its edges: three strokes per side
    sides = (None,) + ((len(strokes) // 3,) if prism and len(strokes) % 3 == 0 else ())
    try:  # C may mix up the strokes' roles: read them from the geometry too
        frame = face_frame(face, cam, np.concatenate(strokes))
    except FitError:  # the strokes miss a curved f: C's roles alone
        frame = None
    tolerances = () if frame is None else PRISM_CHORD_TOLERANCES if prism else (None,)
    for tol in tolerances:
        for count in sides:
            # the second set of alike chords: f's outline may run along n_f's image too
            for group in (0, 1) if prism and tol is not None else (0,):
                try:
                    roles = stroke_roles(strokes, frame, cam, prism, tol, count, group)
                except FitError:
                    continue
                if roles not in readings:
                    readings.append(roles)
    fits, first = [], None
    for reading in readings:
        try:
            # regularized after the choice of face and reading (regularize_operation)
            fits.append((fit(solid, face, cam, strokes, reading, options.option), reading))
        except FitError as e:
            first = first or e
    if not fits:
        raise first
    return [(op, index, labels) for _, op, labels in _scored_readings(fits, solid, ctx)]


def _scored_readings(
    fits: list[tuple[PrismFit | SweepFit, list[int]]], solid: cq.Shape, ctx: Context
) -> list[tuple[float, Operation, list[int]]]:
    """Each (fit, stroke roles) as (score, operation, roles), the best first
    (`verify.reading_score`). A primitive's joint refinement costs more than the rest of
    its fit, and readings of the roles far apart before it refine to nearly one
    primitive: of several readings only those within REFINE_WITHIN of the closest
    unrefined one (by mean distance) are refined
    (docs/NOTES.md, stop 26), and a lone prism is refined without being scored first. A
    refined sweep is a reading beside the fitted one, each scored: the refinement's
    robust loss is not the score, and OCCT refuses some refined profiles (docs/NOTES.md,
    stop 29).

    A reading whose own sketch cannot be drawn (OperationError: an outline that leaves a
    curved face) is dropped; the others stand.

    Raises:
        OperationError: no reading could be scored (the first one's reason).
    """
    errors: list[OperationError] = []

    def distances(op: Operation) -> tuple[np.ndarray, ...] | None:
        try:
            return ctx.sketch_distances(solid, op)
        except OperationError as e:
            errors.append(e)
            return None

    before = {
        id(got): distances(got.operation)
        for got, _ in fits
        if len(fits) > 1 or isinstance(got, SweepFit)
    }
    apart = {k: np.inf if d is None else mean_distance(d) for k, d in before.items()}
    closest = min(apart.values(), default=np.inf)
    scored = []
    for got, roles in sorted(fits, key=lambda f: apart.get(id(f[0]), np.inf)):
        if apart.get(id(got)) == np.inf:
            continue  # its sketch could not be drawn
        far = apart.get(id(got), closest) > REFINE_WITHIN * closest
        op = got.operation if far else got.refined()
        after = distances(op)
        if isinstance(got, SweepFit) and op is not got.operation:
            # the fitted sweep stays a reading: the better one first, and the other one
            # built if that one is not a valid solid (OCCT refuses some refined profiles)
            scored.append((reading_score(before[id(got)]), got.operation, roles))
        if after is not None:
            scored.append((reading_score(after), op, roles))
        if isinstance(got, SweepFit) and not far and not got.straight:
            line = got.refined(straight=True)
            straight = distances(line)
            if straight is not None:
                scored.append((reading_score(straight), line, roles))
    if not scored:
        raise errors[0]
    return sorted(scored, key=lambda f: f[0])


def _fit_bevel_readings(
    solid: cq.Shape, index: int, curve: np.ndarray, ctx: Context, options: InterpretOptions
) -> list[Fit]:
    """The bevel on face `index` whose profile l is the stroke C votes for most or, when
    that reading's own sketch lies more than GOOD_FIT_PX from the strokes, the one of
    the next stroke if it explains them better: C sometimes takes l' for l, and l' back
    projected onto f's plane lands at another corner. A bevel has no Boolean, so
    `options` has nothing for it.

    Returns:
        [(operation, face used, per-stroke labels)].
    """
    strokes, cam = ctx.strokes, ctx.camera
    low = CURVE_THRESHOLDS[OperatorType.BEVEL][0]
    votes = [float((sample_map(curve, resample(s)) > low).sum()) for s in strokes]
    best, first = None, None
    for pick in np.argsort(votes)[::-1][:BEVEL_READINGS]:
        faces = [index]
        under = face_under_stroke(strokes[pick], ctx.maps.face_id)
        if under is not None and under != index and face_at(solid, under).geomType() == "PLANE":
            # the profile l lies on f by definition: when F points elsewhere, the
            # stroke's own face may be the one it was drawn on; or, l running along f's
            # edges, a hand's stroke strays onto the next face (held-out level 3)
            faces.append(under)
        for face_index in faces:
            try:
                got = bevel_fit(solid, face_at(solid, face_index), cam, strokes[pick])
                error = mean_distance(ctx.sketch_distances(solid, got.operation))
            except (FitError, OperationError) as e:
                first = first or e
                continue
            if best is None or error < best[0]:
                best = (error, got, face_index, [int(i == pick) for i in range(len(strokes))])
        if best is not None and best[0] <= GOOD_FIT_PX:
            break
    if best is None:
        raise first
    _, got, face_index, labels = best
    # l refined against every stroke is a reading beside l fitted to its own stroke, the
    # one that explains the strokes better first (a refined l may be refused by OCCT); a
    # refined l whose sketch cannot be drawn is dropped (the fitted one's was drawn above)
    scored = []
    for op in (got.refined(strokes), got.operation):
        try:
            scored.append((reading_score(ctx.sketch_distances(solid, op)), op))
        except OperationError:
            continue
    return [(op, face_index, labels) for _, op in sorted(scored, key=lambda r: r[0])]


_FIT_ON_FACE = per_operator(
    {
        OperatorType.EXTRUDE: _fit_extrude_on_face,
        OperatorType.BEVEL: _fit_bevel_readings,
        OperatorType.ADDSUB: _fit_prism_on_face,
        OperatorType.SWEEP: _fit_sweep_on_face,
    },
    "_FIT_ON_FACE",
)


def apply_with_symmetry(
    solid: cq.Shape, op: Operation, symmetry: str | None, result: cq.Solid | None = None
) -> tuple[tuple[Operation, ...], cq.Solid]:
    """Apply the operation (unless its `result` is given) and, if asked, its mirror image
    through a mid-plane."""
    result = apply_operation(solid, op) if result is None else result
    if symmetry is None:
        return (op,), result
    origin, normal = mid_plane(solid, symmetry)
    mirrored = reflect(op, origin, normal)
    if _rounds_the_same_edge(op, mirrored):
        return (op,), result
    return (op, mirrored), apply_operation(result, mirrored)


def _rounds_the_same_edge(op: Operation, mirrored: Operation) -> bool:
    """A bevel along a whole edge that the mirror plane cuts in half: its image swaps c and
    c' and would round the edge already rounded (the step refuses such a corner)."""
    if op.type is not OperatorType.BEVEL:
        return False
    ends = np.array([op.corner, op.opposite], float)
    image = np.array([mirrored.opposite, mirrored.corner], float)
    return bool(np.allclose(ends, image, rtol=0, atol=1e-9 * max(1.0, float(np.abs(ends).max()))))


def _alternative(
    solid: cq.Shape, other: Reading | None, options: InterpretOptions
) -> Alternative | None:
    """The step's Alternative from the reading not taken (`Reading.alternative`), with
    its mirror image if asked; None when there is none or that image does not build."""
    if other is None:
        return None
    try:
        ops, result = apply_with_symmetry(solid, other.op, options.symmetry, other.result)
    except OperationError:
        return None
    return Alternative(ops, result, other.score)


def check_sketch(strokes: list[np.ndarray]) -> None:
    """Refuse at once what no operation can be read from: too many strokes or points for a
    sketch a person draws (the fitting's cost grows with them), non-finite points, or
    strokes that span less than MIN_SPAN_PX (a dot).

    Raises:
        InterpretError: saying which.
    """
    if not strokes:
        raise InterpretError("no strokes: draw the operation's edges over the model")
    if len(strokes) > MAX_STROKES:
        raise InterpretError(
            f"{len(strokes)} strokes: one operation takes at most "
            f"{MAX_STROKES}; clear the strokes and draw it again"
        )
    points = sum(len(s) for s in strokes)
    if points > MAX_POINTS:
        raise InterpretError(f"{points} stroke points: at most {MAX_POINTS} per operation")
    every = np.concatenate([np.asarray(s, float).reshape(-1, 2) for s in strokes])
    if not np.isfinite(every).all():
        raise InterpretError("a stroke point is not a finite number")
    if float(np.ptp(every, axis=0).max()) < MIN_SPAN_PX:
        raise InterpretError(
            f"the strokes span less than {MIN_SPAN_PX} pixels: draw the "
            "operation's edges, not a dot"
        )


def _read_operators(
    solid: cq.Shape,
    order: list[OperatorType],
    probs: np.ndarray,
    predictor: Predictor,
    ctx: Context,
    options: InterpretOptions,
    times: dict[str, float],
    errors: list[str],
    read: list[tuple[float, OperatorType, Reading]],
) -> None:
    """Read the operators of `order` (taken from it, but for those too unlikely to replace
    a reading) until one reads the strokes within GOOD_FIT_PX, adding (score, operator,
    reading) to `read`: the first reading when `read` is empty, and any later one that may
    replace the best there (see OVERRULE_PROB), the score its reprojection error plus
    PRIOR_PX per decade of the classifier's doubt. Why the others did not fit goes to
    `errors`; seconds spent go to `times`."""
    for kind in list(order):
        p = float(probs[CLASSES.index(kind)])
        if read and p < OVERRULE_PROB:
            continue  # too unlikely to replace a reading (kept for a later call)
        order.remove(kind)
        ta = time.perf_counter()
        face_prob, curve = predictor.segment(ctx.inputs, kind)
        tb = time.perf_counter()
        times["networks"] += tb - ta
        try:
            reading = read_operation(solid, kind, face_prob, curve, ctx, options)
        except (FitError, OperationError) as e:
            errors.append(f"read as {kind.value}, but {e}")
            continue
        finally:
            times["fitting"] += time.perf_counter() - tb
        good = reading.error <= GOOD_FIT_PX
        score = reading.error + PRIOR_PX * -np.log10(max(p, 1e-12))
        if (
            not read
            or good
            or (score <= RESCUE_SCORE_PX and min(read, key=lambda r: r[0])[2].doubtful)
        ):
            read.append((score, kind, reading))
        if good:
            break


def interpret(
    solid: cq.Shape,
    strokes: list[np.ndarray],
    view: OrthoCamera,
    predictor: Predictor,
    renderer: MapRenderer | None = None,
    options: InterpretOptions = InterpretOptions(),
    op_type: OperatorType | None = None,
) -> Interpretation:
    """Read one sketch step over `solid` as an operation and apply it.

    Args:
        solid: the current model (not modified).
        strokes: pixel polylines (K, 2) in `view`'s pixels.
        view: the orthographic camera the strokes were drawn in.
        predictor: the networks.
        renderer: a reusable MapRenderer (one is made if None).
        options: regularization, forced option, symmetry plane.
        op_type: force the operator instead of the classifier's choice (without it,
            the operators are read in the order of the classifier's probabilities, only
            those a chosen Boolean applies to when there is one (TAKE_A_BOOLEAN), until
            one reads the strokes within GOOD_FIT_PX, and the reading with the best score
            is kept: see PRIOR_PX).
    Raises:
        InterpretError: with the reason, when the sketch matches no operation.
    """
    check_sketch(strokes)
    solid = solid.copy()  # rendering meshes it and fitting adds p-curves: the caller's stays
    t0 = time.perf_counter()
    ctx = to_context(solid, strokes, view, renderer or MapRenderer())
    if hasattr(predictor, "observe"):  # a structured predictor reads strokes and faces
        predictor.observe(ctx.strokes, ctx.maps.face_id)
    t1 = time.perf_counter()
    probs = np.asarray(predictor.classify(ctx.inputs), float)
    t2 = time.perf_counter()
    order = [op_type] if op_type else [CLASSES[k] for k in np.argsort(-probs, kind="stable")]
    if options.option is not None and op_type is None:
        # a Boolean is a primitive's: a designer who chose one draws a prism or a sweep,
        # however sure the classifier is of another operator (a radial shrink of a pipe
        # draws nearly the circles of the bore drawn into it)
        order = [k for k in order if k in TAKE_A_BOOLEAN]
    times = {"networks": t2 - t1, "fitting": 0.0}
    read, errors = [], []
    while True:
        _read_operators(solid, order, probs, predictor, ctx, options, times, errors, read)
        if not read:
            more = (
                " (read as any other operator, the strokes did not fit either)"
                if len(errors) > 1
                else ""
            )
            if options.option is not None and op_type is None:
                more += f" (with {options.option.value} chosen, only prisms and sweeps are read)"
            raise InterpretError(errors[0] + more) from None
        read.sort(key=lambda r: r[0])
        _, kind, reading = read.pop(0)
        tb = time.perf_counter()
        try:
            op, snaps, built, unsnapped = reading.op, (), reading.result, ""
            if options.regularize:
                op, snaps, built, unsnapped = _snapped(solid, reading, ctx, view, options)
            tc = time.perf_counter()
            times["fitting"] += tc - tb
            ops, result = apply_with_symmetry(solid, op, options.symmetry, built)
            other = _alternative(solid, reading.alternative, options)
            break
        except (FitError, OperationError) as e:
            times["fitting"] += time.perf_counter() - tb
            errors.append(f"read as {kind.value}, but {e}")
    td = time.perf_counter()
    confidence = float(probs[CLASSES.index(kind)])
    fit = (
        SketchFit.of_distances(*reading.explained[:2], confidence)
        if op is reading.op
        else SketchFit.of(solid, op, ctx.camera, ctx.strokes, confidence)
    )
    return Interpretation(
        ops,
        result,
        kind,
        {c.value: float(p) for c, p in zip(CLASSES, probs)},
        reading.index,
        reading.labels,
        ctx.camera,
        {
            "render": 1e3 * (t1 - t0),
            "networks": 1e3 * times["networks"],
            "fitting": 1e3 * (times["fitting"] - ctx.build_s),
            "brep": 1e3 * (ctx.build_s + td - tc),
            "total": 1e3 * (td - t0),
        },
        other,
        fit,
        snaps,
        unsnapped,
    )
