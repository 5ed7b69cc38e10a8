# SPDX-License-Identifier: LGPL-2.1-or-later
"""The most any reading of an extrusion's strokes can recover: an information bound.

The generator (`datagen.strokes.perturb`) draws each curve as one stroke whose two end
points move by independent Gaussians (sigma per axis from the noise level), the move
spread linearly along the stroke, with a wobble across it that is noise of its own. So
the strokes tell d only through the tips drawn at the moved face's corners: each such tip
is c_i + d s + e, where c_i is corner i's image, s the image of the face's unit normal
(one vector: the camera is orthographic) and e ~ N(0, sigma^2 I). Given f and which tip
was drawn from which corner (an oracle knows them, the pipeline has to infer them), the
likelihood of d is Gaussian around the least-squares d_ML with sd sigma / sqrt(k |s|^2)
for k such tips.

With the generator's prior on d (|d| uniform in `EXTRUDE_D` x `DIAG`, either sign), the
decision that maximises the chance of passing the recovery test (volume IoU >= 0.95)
takes the d whose posterior probability of passing is largest; the two solids nest (one
face moved along its normal), so their IoU is the smaller volume over the larger. That
probability, averaged over samples, bounds what any reading of these strokes can expect
to recover: the oracle knows more than a reading does, and no rule can beat the best
posterior decision on the information it uses.

Left out, so the bound is slightly loose: tips where an occluder cut a stroke (they are
not at a corner and are skipped) and faces whose outline has curved edges.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from tqdm import tqdm

from datagen.dataset import Dataset
from datagen.operations import DIAG, EXTRUDE_D
from datagen.sample import Sample
from datagen.strokes import noise_sigma
from Sketch2CADWorkbench.brep.compare import volume_iou
from Sketch2CADWorkbench.brep.faces import FaceFrame, OperationError, resolve_face
from Sketch2CADWorkbench.brep.operators import apply_operation, replay
from Sketch2CADWorkbench.brep.protocol import Extrude, OperatorType
from Sketch2CADWorkbench.inference.fitting.extrude import offset_from_ends
from Sketch2CADWorkbench.sketch.labels import EXTRUDE_PROFILE
from training.recovery import RECOVERY_IOU

DECISION_GRID = 41  # candidate d's across d_ML +- SPAN_SD sd: 0.2 sd apart
SPAN_SD = 4.0  # the posterior outside +-4 sd holds < 1e-4


@dataclass
class ExtrusionBound:
    """What the strokes of one extrusion sample allow.

    Attributes:
        d_true: the sampled d (mm).
        d_ml: the oracle's least-squares d (mm), from `tips` tips at moved corners.
        sd: the likelihood's standard deviation (mm).
        d_best: the decision most likely to pass the recovery test (mm).
        p_best: the posterior probability that `d_best` passes it.
        ml_recovered, best_recovered: did d_ml / d_best pass it against the truth.
    """

    d_true: float
    d_ml: float
    sd: float
    tips: int
    d_best: float
    p_best: float
    ml_recovered: bool
    best_recovered: bool


def moved_corner_tips(
    sample: Sample, corners_px: np.ndarray, step_px: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Tips (k, 2) drawn at moved corners and the corners' images (k, 2) they belong to.

    The oracle pairs by the truth: a profile stroke runs from a corner to its moved copy
    (its end nearer the moved copy is the moved tip; whichever corner fits both ends
    best), an offset stroke's two ends lie at moved corners (each the nearest). Tips
    farther than 4 sigma from their corner were cut by an occluder and are skipped.
    """
    sigma = noise_sigma(sample.noise_level, sample.camera.width, sample.camera.height)
    moved = corners_px + sample.operation.d * step_px
    tips, owners = [], []
    for stroke, part in zip(sample.strokes, sample.stroke_parts, strict=True):
        a, b = np.asarray(stroke[0], float), np.asarray(stroke[-1], float)
        if part == EXTRUDE_PROFILE:
            fit_ab = np.linalg.norm(corners_px - a, axis=1) + np.linalg.norm(moved - b, axis=1)
            fit_ba = np.linalg.norm(corners_px - b, axis=1) + np.linalg.norm(moved - a, axis=1)
            i, j = int(np.argmin(fit_ab)), int(np.argmin(fit_ba))
            pairs = [(b, i)] if fit_ab[i] <= fit_ba[j] else [(a, j)]
        else:
            pairs = [(t, int(np.argmin(np.linalg.norm(moved - t, axis=1)))) for t in (a, b)]
        for tip, i in pairs:
            if np.linalg.norm(tip - moved[i]) <= 4.0 * sigma:
                tips.append(tip)
                owners.append(corners_px[i])
    return np.array(tips).reshape(-1, 2), np.array(owners).reshape(-1, 2)


def extrusion_bound(sample: Sample) -> ExtrusionBound | None:
    """The bound's figures for one extrusion sample, or None when they do not apply (the
    face is curved, or no tip was drawn at a moved corner)."""
    context = replay(sample.context)[-1]
    op = sample.operation
    ref = resolve_face(context, op.face)
    if ref.surface is not None:
        return None
    normal = np.asarray(FaceFrame.of(ref.face).normal, float)
    corners = np.array([v.toTuple() for v in ref.face.Vertices()])
    cam = sample.camera
    corners_px = cam.project(corners)[0]
    step_px = cam.image_of(normal)
    tips, owners = moved_corner_tips(sample, corners_px, step_px)
    if not len(tips) or step_px @ step_px == 0:
        return None
    sigma = noise_sigma(sample.noise_level, cam.width, cam.height)
    d_ml = offset_from_ends(tips, owners, step_px)
    sd = float(sigma / np.sqrt(len(tips) * (step_px @ step_px)))

    lo, hi = (v * DIAG for v in EXTRUDE_D)
    grid = decision_grid(d_ml, sd)
    grid = grid[(np.abs(grid) >= lo) & (np.abs(grid) <= hi)]  # the prior's support
    volumes = np.array([_volume(context, op, d) for d in grid])
    truth = apply_operation(context, op)
    d_best, p_best = best_decision(grid, volumes, d_ml, sd)
    return ExtrusionBound(
        float(op.d),
        d_ml,
        sd,
        len(tips),
        d_best,
        p_best,
        _recovered(context, op, d_ml, truth),
        _recovered(context, op, d_best, truth),
    )


def decision_grid(ml: float, sd: float) -> np.ndarray:
    """The candidate decisions: DECISION_GRID values across ml +- SPAN_SD sd."""
    return np.linspace(ml - SPAN_SD * sd, ml + SPAN_SD * sd, DECISION_GRID)


def best_decision(
    grid: np.ndarray, volumes: np.ndarray, ml: float, sd: float
) -> tuple[float, float]:
    """The decision of `grid` most likely to pass the recovery test, and that posterior
    probability, for a parameter whose solids nest (their IoU is the smaller volume over
    the larger) with a Gaussian likelihood around `ml` (sd `sd`) and a flat prior over
    the grid. Grid values whose solid did not build (volume NaN) are left out; with
    fewer than two left, (ml, NaN)."""
    keep = np.isfinite(volumes)
    grid, volumes = grid[keep], volumes[keep]
    if len(grid) < 2:
        return ml, float("nan")
    weight = np.exp(-0.5 * ((grid - ml) / sd) ** 2)
    weight /= weight.sum()
    pairs = volumes[:, None], volumes[None]
    iou = np.minimum(*pairs) / np.maximum(*pairs)
    p_pass = np.minimum((iou >= RECOVERY_IOU) @ weight, 1.0)
    best = np.flatnonzero(p_pass >= p_pass.max() - 1e-9)  # ties: the nearest to ml
    i = best[int(np.argmin(np.abs(grid[best] - ml)))]
    return float(grid[i]), float(p_pass[i])


def _volume(context, op: Extrude, d: float) -> float:
    try:
        return float(apply_operation(context, Extrude(op.face, float(d))).Volume())
    except OperationError:
        return float("nan")


def _recovered(context, op: Extrude, d: float, truth) -> bool:
    try:
        return (
            volume_iou(apply_operation(context, Extrude(op.face, float(d))), truth) >= RECOVERY_IOU
        )
    except OperationError:
        return False


def bound_of_set(data: str, limit: int | None = None) -> dict:
    """The bound over a generated set's extrusions on planar faces (the first `limit`
    samples): the oracle's rate, the best decision's rate and its expected rate (the mean
    posterior probability of passing: the bound), with how many samples count."""
    return summary(bounds_over_set(data, limit, OperatorType.EXTRUDE, extrusion_bound))


def bounds_over_set(
    data: str, limit: int | None, kind: OperatorType, bound: Callable[[Sample], Any]
) -> tuple[list, int]:
    """`bound` of each sample of operator `kind` among a set's first `limit` samples
    (those it applies to: not None), and how many samples of `kind` there were."""
    ds = Dataset(data)
    total = len(ds) if limit is None else min(limit, len(ds))
    rows, drawn = [], 0
    with tqdm(total=total, desc=f"bound {data}", unit="sample", leave=False) as bar:
        for k in ds.shards:
            for s in ds.samples(k):
                if bar.n >= total:
                    break
                bar.update(1)
                if s.op_type is kind:
                    drawn += 1
                    got = bound(s)
                    if got is not None:
                        rows.append(got)
    return rows, drawn


def summary(found: tuple[list, int]) -> dict:
    """The rates over `bounds_over_set`'s rows (each with ml_recovered, best_recovered
    and p_best): how many count, of how many drawn."""
    rows, drawn = found
    p = [r.p_best for r in rows if np.isfinite(r.p_best)]
    return {
        "n": len(rows),
        "drawn": drawn,
        "oracle_ml_rate": float(np.mean([r.ml_recovered for r in rows])) if rows else None,
        "best_decision_rate": float(np.mean([r.best_recovered for r in rows])) if rows else None,
        "expected_bound": float(np.mean(p)) if p else None,
    }
