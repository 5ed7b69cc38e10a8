# SPDX-License-Identifier: LGPL-2.1-or-later
"""Each operator's fitting on one base face, from the networks' C map to operations.

    fit_on_face(solid, op_type, face index, C, ctx, options) -> [(operation, face, labels)]

The fitting/ package fits one operator to strokes whose roles are known; these adapters
decide the roles (C's, and those read from the strokes' geometry), try the readings
they allow, and rank the operations by how well their own sketches explain the strokes
(`SketchFit.score`), the best first: an extrusion by a line search then a search on
that score, a bevel by the strokes C votes for as its profile, a prism or a sweep by each
reading of the stroke roles, a shell by its rim (the strokes' geometry alone: the networks
do not know it).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import cadquery as cq
import numpy as np
from scipy.optimize import minimize_scalar

from ..brep.faces import OperationError, base_face_index, face_at, model_scale, resolve_face
from ..brep.protocol import EdgeSet, Extrude, Operation, OperatorType, per_operator
from ..sketch.labels import CURVE_THRESHOLDS, SHELL_RIM, SHELL_WALL
from .context import Context
from .drawing import CORNER_REACH
from .fitting.addsub import PrismFit, prism_fits
from .fitting.base_face import face_under_stroke
from .fitting.bevel import bevel_fit
from .fitting.common import FitError, classify_strokes, resample, sample_map
from .fitting.extrude import fit_extrude, fit_extrude_by_ends
from .fitting.rounds import round_fits
from .fitting.shell import rim_and_wall, shell_fit, thickest_that_builds
from .fitting.stroke_roles import PRISM_CHORD_TOLERANCES, stroke_roles, whole_outline_roles
from .fitting.surface import face_frame
from .fitting.sweep import SweepFit, sweep_fit
from .fitting.verify import SketchFit
from .options import InterpretOptions
from .reading import GOOD_FIT_PX, Fit

# An extrusion's d is also searched by the score its readings are ranked by, around the
# line search's readings (their range widened by SCORE_SEARCH_SPAN of d or SCORE_SEARCH_PX,
# whichever is more) in at most SCORE_SEARCH_STEPS scorings: held-out extrusions read so
# beside the line search's, level 1 88.5 -> 91.7% recovered, level 3 66.7 -> 67.3% (mean
# volume IoU .943 -> .952); 20 steps read the same as 10 (see docs/measurements.md,
# adapters.SCORE_SEARCH_SPAN, SCORE_SEARCH_PX and SCORE_SEARCH_STEPS).
SCORE_SEARCH_SPAN = 0.1
SCORE_SEARCH_PX = 8.0
SCORE_SEARCH_STEPS = 10
# Strokes tried as the bevel's profile l, in the order of C's votes.
BEVEL_READINGS = 2
# Of a prism's readings of the stroke roles, those whose unrefined sketch lies within
# this factor of the closest one's distance from the strokes are refined: readings
# farther apart refined to within 0.1 px of each other on held-out level 1 (see
# docs/measurements.md, adapters.REFINE_WITHIN).
REFINE_WITHIN = 1.5


def fit_on_face(
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
    EXTRUDE_MISMATCH_PX from the strokes). Elsewhere (a disk, an outline with arcs), or when
    no stroke pairs with a curve, or that reading is refused, the paper's line search:
    d read with the strokes' ends (`fit_extrude`'s LINE_SEARCH_END_WEIGHT) and d read by closeness
    alone when that differs, the one that explains the strokes better (`SketchFit.score`)
    first, the other built if that one is refused (a top pushed down past a hole's rim,
    say, falls apart)."""
    face = face_at(solid, index)
    strokes, cam = ctx.strokes, ctx.camera
    labels = classify_strokes(strokes, curve, CURVE_THRESHOLDS[OperatorType.EXTRUDE][:1])
    offset, sides = (
        [s for s, l in zip(strokes, labels, strict=True) if l == part] for part in (1, 0)
    )
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
            return ctx.sketch_fit(solid, op).score
        except OperationError:
            return np.inf

    best = _extrusion_by_score(ops, score, cam.pixel_size, 1e-6 * model_scale(solid))
    if best not in ops:
        ops.append(best)
    return [(op, index, labels) for op in sorted(ops, key=score)]


def _extrusion_by_score(
    ops: list[Extrude], score: Callable[[Operation], float], pixel: float, least: float
) -> Extrude:
    """The extrusion whose d minimises `score` (`SketchFit.score`, the score readings
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
    return _fit_by_roles(prism_fits, OperatorType.ADDSUB, solid, index, curve, ctx, options)


def _fit_sweep_on_face(
    solid: cq.Shape, index: int, curve: np.ndarray, ctx: Context, options: InterpretOptions
) -> list[Fit]:
    """The sweep on face `index` (`_fit_by_roles`)."""
    return _fit_by_roles(
        lambda *args: [sweep_fit(*args)], OperatorType.SWEEP, solid, index, curve, ctx, options
    )


def _primitive_roles(
    op_type: OperatorType, solid: cq.Shape, index: int, curve: np.ndarray, ctx: Context
) -> list[list[int]]:
    """The stroke roles a primitive on face `index` is fitted by (`_fit_by_roles`): C's,
    then those read from the strokes' geometry, each once."""
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
    if prism and frame is not None:
        # drawn without its hidden lines: one outline whole, few side edges
        try:
            whole = whole_outline_roles(strokes, frame, cam, CORNER_REACH * cam.width)
        except FitError:
            whole = []
        if whole and whole not in readings:
            readings.append(whole)
    return readings


def _fit_by_roles(
    fit: Callable[..., list[PrismFit] | list[SweepFit]],
    op_type: OperatorType,
    solid: cq.Shape,
    index: int,
    curve: np.ndarray,
    ctx: Context,
    options: InterpretOptions,
) -> list[Fit]:
    """A primitive (prism or sweep) `fit` on face `index` by the stroke roles C gives and
    by those read from the strokes' geometry (`fit` gives one reading of the primitive
    per roles, or more), the one whose own sketch lies closest to
    the strokes first. All are kept: a thin slot seen nearly along f's normal also
    reads, a little closer, as a tall post on its end, which a chosen subtract refuses
    (it cuts nothing), and then the slot's own roles are the step."""
    face = face_at(solid, index)
    strokes, cam = ctx.strokes, ctx.camera
    key = (solid, op_type, index)
    if key not in ctx.roles:  # alike for either Boolean: the other one is fitted again
        ctx.roles[key] = _primitive_roles(op_type, solid, index, curve, ctx)
    readings = ctx.roles[key]
    fits: list[tuple[PrismFit | SweepFit, list[int]]] = []
    first = None
    for reading in readings:
        try:
            # regularized after the choice of face and reading (regularize_operation)
            got = fit(solid, face, cam, strokes, reading, options.option)
            fits.extend((one, reading) for one in got)
        except FitError as e:
            first = first or e
    if not fits:
        raise first
    return [(op, index, labels) for _, op, labels in _scored_readings(fits, solid, ctx)]


def _scored_readings(
    fits: list[tuple[PrismFit | SweepFit, list[int]]], solid: cq.Shape, ctx: Context
) -> list[tuple[float, Operation, list[int]]]:
    """Each (fit, stroke roles) as (score, operation, roles), the best first
    (`SketchFit.score`). A primitive's joint refinement costs more than the rest of
    its fit, and readings of the roles far apart before it refine to nearly one
    primitive: of several readings only those within REFINE_WITHIN of the closest
    unrefined one (by misfit_px) are refined, and a lone prism is refined without
    being scored first. A refined sweep is a reading beside the fitted one, each scored:
    the refinement's robust loss is not the score, and OCCT refuses some refined
    profiles.

    A reading whose own sketch cannot be drawn (OperationError: an outline that leaves a
    curved face) is dropped; the others stand.

    Raises:
        OperationError: no reading could be scored (the first one's reason, or that every
            reading's sketch lies outside the view: infinitely far from the strokes).
    """
    errors: list[OperationError] = []

    def fit_of(op: Operation) -> SketchFit | None:
        try:
            return ctx.sketch_fit(solid, op)
        except OperationError as e:
            errors.append(e)
            return None

    before = {
        id(got): fit_of(got.operation)
        for got, _ in fits
        if len(fits) > 1 or isinstance(got, SweepFit)
    }
    apart = {k: np.inf if d is None else d.misfit_px for k, d in before.items()}
    closest = min(apart.values(), default=np.inf)
    scored = []
    for got, roles in sorted(fits, key=lambda f: apart.get(id(f[0]), np.inf)):
        if apart.get(id(got)) == np.inf:
            continue  # its sketch could not be drawn
        far = apart.get(id(got), closest) > REFINE_WITHIN * closest
        op = got.operation if far else got.refined()
        after = fit_of(op)
        if isinstance(got, SweepFit) and op is not got.operation:
            # the fitted sweep stays a reading: the better one first, and the other one
            # built if that one is not a valid solid (OCCT refuses some refined profiles)
            scored.append((before[id(got)].score, got.operation, roles))
        if after is not None:
            scored.append((after.score, op, roles))
        if isinstance(got, SweepFit) and not far and not got.straight:
            line = got.refined(straight=True)
            straight = fit_of(line)
            if straight is not None:
                scored.append((straight.score, line, roles))
    if not scored:
        raise (
            errors[0]
            if errors
            else OperationError(
                "the sketch of every reading lies wholly outside the view, so none could be "
                "compared with the strokes"
            )
        )
    return sorted(scored, key=lambda f: f[0])


def _fit_bevel_readings(
    solid: cq.Shape, index: int, curve: np.ndarray, ctx: Context, options: InterpretOptions
) -> list[Fit]:
    """The bevel on face `index` whose profile l is the stroke C votes for most or, when
    that reading's own sketch lies more than GOOD_FIT_PX from the strokes, the one of
    the next stroke if it explains them better: C sometimes takes l' for l, and l' back
    projected onto f's plane lands at another corner. Beside them, the bevels with l
    drawn across an edge (`_across_readings`); all of them follow the designer's edge
    set (`options.edges`; a corner's crease has no outline of its own to follow, and
    follows its crease then).

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
                misfit = ctx.sketch_fit(solid, got.operation).misfit_px
            except (FitError, OperationError) as e:
                first = first or e
                continue
            if best is None or misfit < best[0]:
                best = (misfit, got, face_index, [int(i == pick) for i in range(len(strokes))])
        if best is not None and best[0] <= GOOD_FIT_PX:
            break
    scored = []
    if best is not None:
        _, got, face_index, labels = best
        # l refined against every stroke is a reading beside l fitted to its own stroke,
        # the one that explains the strokes better first (a refined l may be refused by
        # OCCT); a refined l whose sketch cannot be drawn is dropped (the fitted one's was
        # drawn above)
        edges = EdgeSet.DRAWN if options.edges is EdgeSet.OUTLINE else options.edges
        for op in (got.refined(strokes), got.operation):
            try:
                op = replace(op, edges=edges)
                scored.append((ctx.sketch_fit(solid, op).score, op, face_index, labels))
            except OperationError:
                continue
    if (
        options.edges is not EdgeSet.DRAWN
        or min((r[0] for r in scored), default=np.inf) > GOOD_FIT_PX
    ):
        # a crease that explains the strokes clearly is their reading; an edge set the
        # designer chose, or no clear crease, asks for the profile drawn across an edge
        scored += _across_readings(solid, strokes, votes, ctx, options)
    if not scored:
        raise first or FitError("bevel: no reading of the profile stroke builds")
    return [
        (op, face_index, labels) for _, op, face_index, labels in sorted(scored, key=lambda r: r[0])
    ]


def _across_readings(
    solid: cq.Shape,
    strokes: list[np.ndarray],
    votes: list[float],
    ctx: Context,
    options: InterpretOptions,
) -> list[tuple[float, Operation, int, list[int]]]:
    """Bevels whose profile l, one of the BEVEL_READINGS strokes C votes for most (C
    takes l' for l as often: the designer draws both alike), is drawn across an edge: a
    straight edge or a circular rim (fitting/rounds), with the designer's edge set, and
    their scores; none where no edge fits (a corner's crease reads it then)."""
    out: list[tuple[float, Operation, int, list[int]]] = []
    for pick in np.argsort(votes)[::-1][:BEVEL_READINGS]:
        others = [s for i, s in enumerate(strokes) if i != pick]
        try:
            ops = round_fits(solid, ctx.camera, strokes[pick], options.edges, others)
        except (FitError, OperationError):
            continue
        labels = [int(i == pick) for i in range(len(strokes))]
        for op in ops:
            try:
                score = ctx.sketch_fit(solid, op).score
            except OperationError:
                continue
            index = base_face_index(solid, resolve_face(solid, op.face).face)
            out.append((score, op, index, labels))
    return out


def _fit_shell_on_face(
    solid: cq.Shape, index: int, curve: np.ndarray, ctx: Context, options: InterpretOptions
) -> list[Fit]:
    """The shell opening face `index`, t read from the rim its strokes draw (within what
    the solid takes: `thickest_that_builds`); a stroke down
    an inner wall is labelled as such and read no further (fitting/shell.py). The
    networks know no shell: C is not used, nor has `options` anything for it."""
    strokes = ctx.strokes
    drawn = rim_and_wall(strokes)
    face = face_at(solid, index)
    op = shell_fit(solid, face, ctx.camera, [strokes[i] for i in drawn.rim])
    op = thickest_that_builds(solid, face, op)
    labels = [SHELL_WALL if i == drawn.wall else SHELL_RIM for i in range(len(strokes))]
    return [(op, index, labels)]


_FIT_ON_FACE = per_operator(
    {
        OperatorType.EXTRUDE: _fit_extrude_on_face,
        OperatorType.BEVEL: _fit_bevel_readings,
        OperatorType.ADDSUB: _fit_prism_on_face,
        OperatorType.SWEEP: _fit_sweep_on_face,
        OperatorType.SHELL: _fit_shell_on_face,
    },
    "_FIT_ON_FACE",
)
