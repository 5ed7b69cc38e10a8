# SPDX-License-Identifier: LGPL-2.1-or-later
"""The search for a step's reading: over base faces, then over operators.

    read_operation(solid, op_type, F, C, ctx, options) -> Reading     one operator
    read_operators(...)                                               the operators in turn

The paper takes the planar face with the most F > 0.5 pixels and the classifier's
operator. Here both are a search ended by a clear fit (GOOD_FIT_PX): the next faces, then
the next operators, are fitted when the likeliest one does not explain the strokes, and
the best reading by its score wins. The fitting on one face is adapters.py's.

A structured head of five classes (sketch.labels.LABELLED) classifies the shell too.
A classifier of the paper's four (sketch.labels.CLASSES: the U-Net, the shipped head)
does not; with it a shell is proposed by the strokes' geometry (`shell_prior`): when
the strokes close into one rim lying on one planar face, with at most one stroke down
a wall (fitting/shell.rim_and_wall), the shell is read first, as sure as the classifier's
likeliest operator; otherwise it is not read.
"""

from __future__ import annotations

import time
from dataclasses import replace
from typing import Protocol as TypingProtocol

import cadquery as cq
import numpy as np

from ..brep.faces import OperationError, face_at, face_kinds, plane_normals
from ..brep.protocol import AddSubPrism, Operation, OperatorType, Shell, Sweep
from ..render.camera import OrthoCamera
from ..sketch.labels import LABELLED, SHELL_RIM
from .adapters import fit_on_face
from .alternative import drawn_fits, explained, one_way_scores, the_meant
from .context import Context
from .fitting.base_face import face_most_under, face_under_stroke, rank_base_faces
from .fitting.common import FitError, sample_map
from .fitting.primitive import base_centre, base_share, other_option_fits
from .fitting.shell import rim_and_wall
from .fitting.verify import sketch_fit
from .options import InterpretOptions
from .reading import GOOD_FIT_PX, Fit, Reading, builds_a_change

# A face whose outward normal is within this cosine of edge-on, or turned away from the
# view, is one the user cannot see from it.
FACING_COS = 0.05
# A primitive whose base centre lies farther than this (context pixels, in depth) behind
# the surface the view shows there stands where the designer could not see it: the
# outline drawn around a post's top back-projects just as well onto the plate far behind
# it, along the view rays (examples/sessions/lamp.json, step 3). Such a reading ranks
# with those on hidden faces. A few pixels: a centre on f sees f itself (depth equal).
BEHIND_PX = 4.0
# Base faces fitted at most, in the order of the face map's counting; a fit whose own
# sketch lies within GOOD_FIT_PX (mean, both ways) of the strokes ends the search.
BASE_FACE_TRIES = 4
# The operators whose base face may be a cylinder's or cone's side (fitting/surface.py;
# an extrusion of one changes its radius: fitting/extrude.py).
ON_CURVED_FACES = (OperatorType.EXTRUDE, OperatorType.ADDSUB, OperatorType.SWEEP)
# Operators, like faces, are one search: the most probable operator that fits is read
# first, and when its reading lies over GOOD_FIT_PX from the strokes the others are read
# too, in the order of their probability p. Another operator's reading replaces it only
# when the classifier gives it at least OVERRULE_PROB and it reads the strokes within
# GOOD_FIT_PX (a clear fit, not the better of two poor ones: thirty random short strokes
# fit some prism to 3-5 px), and then only if its score, its misfit_px (SketchFit) plus
# PRIOR_PX per decade of doubt (-log10 p), is the lower. When the reading it would replace
# is doubtful (SketchFit), a score within RESCUE_SCORE_PX is enough: a fit just past
# GOOD_FIT_PX that the classifier finds likely (a level-3 extrusion at 3.4 px, p 0.5,
# over a sweep at 53 px), where the prisms thirty random strokes fit score 4.4-8.8. A
# triangle whose edges are all drawn is a prism however sure the classifier is of a sweep
# (p 0.003 against 0.996). An operator under OVERRULE_PROB is read too while the best
# reading is doubtful: the classifier learnt from sketches with every line, and a hole
# drawn without its hidden lines is an extrusion to it (p 1.0), whose reading then lies
# tens of pixels from the strokes where the prism's lies within two. PRIOR_PX is not
# tuned: a decade of doubt weighs about a level-1 hand's error (median misfit 1.4 px);
# see docs/measurements.md, search.PRIOR_PX and OVERRULE_PROB.
PRIOR_PX = 1.0
OVERRULE_PROB = 1e-3
RESCUE_SCORE_PX = GOOD_FIT_PX + PRIOR_PX  # a good fit with one decade of doubt
# The operators the designer's Boolean choice (InterpretOptions.option) applies to: with
# one chosen, only these are read.
TAKE_A_BOOLEAN = (OperatorType.ADDSUB, OperatorType.SWEEP)


class Predictor(TypingProtocol):
    """The networks: operator probabilities, then the operator's F and C maps."""

    def classify(self, inputs: np.ndarray) -> np.ndarray:
        """(5, H, W) inputs S, D, N -> probabilities in sketch.labels.LABELLED order:
        (5,) with the shell, or (4,) for a classifier of the U-Net's classes alone."""

    def segment(self, inputs: np.ndarray, op_type: OperatorType) -> tuple[np.ndarray, np.ndarray]:
        """(5, H, W) inputs -> F (H, W) base-face probability and C (H, W) curve map."""


def shell_prior(solid: cq.Shape, ctx: Context) -> float:
    """How likely the strokes draw a shell's rim, in place of a classifier's probability:
    1 when they close into one rim (`rim_and_wall`) drawn on a planar face of the model
    (`face_most_under`: the face more of its samples on the model lie on than any other;
    a level-3 hand's rim on a thin wall runs onto the next face and into the air), else
    0. Which face it opens is the fitting's: each planar face under a stroke is tried."""
    try:
        drawn = rim_and_wall(ctx.strokes)
    except FitError:
        return 0.0
    face = face_most_under([ctx.strokes[i] for i in drawn.rim], ctx.maps.face_id)
    return 0.0 if face is None else float(face_kinds(solid)[face] == "PLANE")


def classifies_the_shell(predictor: Predictor, ctx: Context) -> bool:
    """Whether the networks have a class, and F and C maps, for the shell (a head of the
    five classes of LABELLED); else `shell_prior` proposes it and its maps are empty."""
    return len(predictor.classify(ctx.inputs)) == len(LABELLED)


def operator_probability(probs: np.ndarray, kind: OperatorType) -> float:
    """The probability of `kind` in the five of sketch.labels.LABELLED (the shell's
    `shell_prior` where the classifier has no shell class)."""
    return float(probs[LABELLED.index(kind)])


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
    then the one whose sketch reprojects best (`SketchFit.score`). A reading that
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
            fits = fit_on_face(solid, op_type, index, curve, ctx, options)
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
                reading.fit.misfit_px <= GOOD_FIT_PX
                and not reading.hidden
                and builds_a_change(solid, reading, ctx)
            ):
                return weigh_the_other_boolean(solid, op_type, reading, curve, ctx, options)
    readings.sort(key=lambda r: (r.hidden, r.fit.score))
    if readings and not builds_a_change(solid, readings[0], ctx):
        # the best reading's other Boolean draws its lines too (paper Fig. 5b): it competes
        # by its score with the rest, before a reading that explains the strokes worse
        readings = sorted(
            readings
            + _with_the_other_boolean(solid, op_type, readings, curve, ctx, options, hidden),
            key=lambda r: (r.hidden, r.fit.score),
        )
    for reading in readings:
        if builds_a_change(solid, reading, ctx):
            return weigh_the_other_boolean(solid, op_type, reading, curve, ctx, options)
    if readings:
        raise FitError(readings[0].refused)
    raise first or FitError("no face of the model gave a reading of the strokes")


def weigh_the_other_boolean(
    solid: cq.Shape,
    op_type: OperatorType,
    reading: Reading,
    curve: np.ndarray,
    ctx: Context,
    options: InterpretOptions,
) -> Reading:
    """Of a primitive's built reading and the one of its other Boolean on its face, the
    one the strokes mean (each scored by its lines drawn each of alternative.LINE_WAYS,
    `_reading`), with the other as its
    `alternative` when that is offered (alternative.py: both weighed by their lines
    drawn the one way that explains the strokes best, and by where each would stand on
    f). Weighed only when the designer chose no Boolean, the reading is not already the
    other Boolean of one that did not build, and its far outline stands on f
    (`other_option_fits`: the other one's base must, to be read); and against an other
    reading that builds a change and is not hidden where the reading is not (both built,
    so both carry their `ways`)."""
    if (
        ctx.renderer is None
        or options.option is not None
        or not isinstance(reading.op, (AddSubPrism, Sweep))
        or reading.flip_refused
        or not other_option_fits(face_at(solid, reading.index), ctx.camera, reading.op)
    ):
        return reading
    hidden = hidden_faces(solid, ctx.camera)
    others = _with_the_other_boolean(solid, op_type, [reading], curve, ctx, options, hidden)
    other = next(
        (r for r in others if r.hidden <= reading.hidden and builds_a_change(solid, r, ctx)),
        None,
    )
    if other is None:
        return reading
    face = face_at(solid, reading.index)
    if not reading.ways or not other.ways:  # nothing built: nothing seen to weigh
        return reading
    # both are primitives: the reading one by the test above, the other fitted like it
    share = [
        base_share(face, ctx.camera, r.op)
        for r in (reading, other)
        if isinstance(r.op, (AddSubPrism, Sweep))
    ]
    flip, offered = the_meant(*one_way_scores(reading.ways, other.ways), (share[0], share[1]))
    taken, left = (other, reading) if flip else (reading, other)
    taken.alternative = left if offered else None
    return taken


def _reading(solid: cq.Shape, fit: Fit, ctx: Context, hidden: set[int]) -> Reading:
    """A fit scored against the strokes (a shell's against its rim's: a stroke down a wall
    says nothing more); hidden when its face is (`hidden_faces`) or it stands behind the
    model. A primitive is built, and scored by its lines drawn the way of
    alternative.LINE_WAYS that explains the strokes best: a designer who leaves the hidden
    lines out draws a hole's rim and what the opening shows, which its lines drawn every
    way explain poorly, and then another operator or the boss on its rim would win."""
    op, used, labels = fit
    fit_ = ctx.sketch_fit(solid, op)
    if isinstance(op, Shell):
        rim = [s for s, label in zip(ctx.strokes, labels, strict=True) if label == SHELL_RIM]
        fit_ = sketch_fit(solid, op, ctx.camera, rim, face=ctx.resolved(solid, op.face))
    reading = Reading(
        fit_,
        op,
        used,
        labels,
        used in hidden or stands_behind_the_model(op, ctx),
    )
    if (
        ctx.renderer is not None
        and isinstance(op, (AddSubPrism, Sweep))
        and builds_a_change(solid, reading, ctx)
        and reading.result is not None
    ):
        reading.ways = drawn_fits(
            solid,
            op,
            reading.result,
            ctx.camera,
            ctx.drawn,
            ctx.renderer,
            ctx.resolved(solid, op.face),
            reading.fit,
        )
        reading.fit = explained(reading.ways)
    return reading


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
        fits = fit_on_face(solid, op_type, best.index, curve, ctx, replace(options, option=other))
    except (FitError, OperationError):
        return []
    # a primitive's fits were scored by `_scored_readings`, which drops any that cannot be
    # drawn: no OperationError to guard against here
    readings = sorted(
        (_reading(solid, fit, ctx, hidden) for fit in fits), key=lambda r: r.fit.score
    )
    for reading in readings:
        reading.flip_refused = True
    return readings


def read_operators(
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
    a reading that is not doubtful) until one reads the strokes within GOOD_FIT_PX (with
    a Boolean chosen, every one: `order` holds the primitives alone, which the
    classifier, shown no choice, does not rank, and their scores decide), adding
    (score, operator, reading) to `read`: the first reading when `read` is empty, and
    any later one that may replace the best there (see OVERRULE_PROB), the score its
    misfit_px plus PRIOR_PX per decade of the classifier's doubt. Why the others did not
    fit goes to `errors`; seconds spent go to `times`."""
    for kind in list(order):
        p = operator_probability(probs, kind)
        best_doubtful = bool(read) and min(read, key=lambda r: r[0])[2].doubtful
        if read and p < OVERRULE_PROB and not best_doubtful:
            # too unlikely to replace a reading that explains the strokes (kept for a
            # later call); one that does not is no reading to keep against a clear fit
            continue
        order.remove(kind)
        ta = time.perf_counter()
        if kind is not OperatorType.SHELL or classifies_the_shell(predictor, ctx):
            face_prob, curve = predictor.segment(ctx.inputs, kind)
        else:  # no evidence from the networks: the faces under the rim are tried
            face_prob = curve = np.zeros(ctx.maps.face_id.shape, np.float32)
        tb = time.perf_counter()
        times["networks"] += tb - ta
        try:
            reading = read_operation(solid, kind, face_prob, curve, ctx, options)
        except (FitError, OperationError) as e:
            errors.append(f"read as {kind.value}, but {e}")
            continue
        finally:
            times["fitting"] += time.perf_counter() - tb
        good = reading.fit.misfit_px <= GOOD_FIT_PX
        score = reading.fit.misfit_px + PRIOR_PX * -np.log10(max(p, 1e-12))
        if not read or good or (score <= RESCUE_SCORE_PX and best_doubtful):
            read.append((score, kind, reading))
        if good and options.option is None:
            break
