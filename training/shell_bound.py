# SPDX-License-Identifier: LGPL-2.1-or-later
"""The most any reading of a shell's rim strokes can recover: an information bound.

The generator draws each side of the rim (f's outline inset by t) as one stroke whose two
end points move by independent Gaussians (`datagen.strokes`, sigma per axis from the
noise level), the move spread linearly along the stroke, with a wobble across it that is
noise of its own. So the strokes tell t through the tips drawn at the rim's corners. On
a polygonal f with no hole and no reflex corner, rim corner i lies at o_i + t b_i (b_i
along the corner's bisector: every side moves in by t), whose image is p_i + t s_i; each
tip drawn there is p_i + t s_i + e, e ~ N(0, sigma^2 I). Given f and which tip belongs to
which corner (an oracle knows them, the pipeline infers them), the likelihood of t is
Gaussian around the least-squares t_ML with sd sigma / sqrt(sum |s_i|^2) over the tips.

With the generator's prior on t (uniform in `SHELL_T` x `DIAG`), the decision that
maximises the chance of passing the recovery test (volume IoU >= 0.95) takes the t whose
posterior probability of passing is largest; the shells nest (a thicker wall holds a
thinner one), so their IoU is the smaller volume over the larger. That probability,
averaged over samples, bounds what any reading of these strokes can expect to recover,
as `training/extrusion_bound.py` bounds an extrusion's d (whose decision it shares).

Left out, so the bound is slightly loose: tips an occluder cut (farther than 4 sigma
from their corner), and faces whose rim has arcs (curved outlines, holes, reflex
corners), where a corner does not move linearly with t.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from datagen.operations import DIAG, SHELL_T
from datagen.sample import Sample
from datagen.strokes import noise_sigma
from Sketch2CADWorkbench.brep.faces import OperationError, resolve_face
from Sketch2CADWorkbench.brep.operators import apply_operation, replay
from Sketch2CADWorkbench.brep.protocol import OperatorType, Shell
from Sketch2CADWorkbench.inference.fitting.common import FitError
from Sketch2CADWorkbench.inference.fitting.shell import shell_fit
from Sketch2CADWorkbench.sketch.curves import rim_wires
from Sketch2CADWorkbench.sketch.labels import SHELL_RIM
from training.extrusion_bound import best_decision, bounds_over_set, decision_grid, summary
from training.recovery import RECOVERY_IOU

# The shell's volume is a cubic in t while no face of the cavity vanishes: built at this
# many t's across the grid and interpolated; where the fit misses a built volume by more
# than VOLUME_FIT_REL, every grid t is built.
VOLUME_SAMPLES = 6
VOLUME_FIT_REL = 1e-6


@dataclass
class ShellBound:
    """What the rim strokes of one shell sample allow (as ExtrusionBound, for t)."""

    t_true: float
    t_ml: float
    sd: float
    tips: int
    t_best: float
    p_best: float
    ml_recovered: bool
    best_recovered: bool
    fit_recovered: bool


def rim_corners(face, t: float) -> np.ndarray | None:
    """The rim's corners (k, 3) for thickness t, or None where the rim is not one
    polygon of lines (an arc: a curved outline, a hole or a reflex corner)."""
    wires = rim_wires(face, t)
    if len(wires) != 1 or any(e.geomType() != "LINE" for e in wires[0].Edges()):
        return None
    return np.array([v.toTuple() for v in wires[0].Vertices()], float)


def shell_bound(sample: Sample) -> ShellBound | None:
    """The bound's figures for one shell sample, or None when they do not apply."""
    op = sample.operation
    if not isinstance(op, Shell):
        return None
    context = replay(sample.context)[-1]
    rf = resolve_face(context, op.face)
    try:
        here, moved = rim_corners(rf.face, op.t), rim_corners(rf.face, op.t * 1.001)
    except OperationError:
        return None
    if here is None or moved is None or len(here) != len(moved):
        return None
    moved = moved[[int(np.argmin(np.linalg.norm(moved - q, axis=1))) for q in here]]
    cam = sample.camera
    here_px, moved_px = cam.project(here)[0], cam.project(moved)[0]
    slope = (moved_px - here_px) / (op.t * 0.001)  # s_i: image pixels per mm of t
    base = here_px - op.t * slope  # p_i: the corners' images at t = 0
    sigma = noise_sigma(sample.noise_level, cam.width, cam.height)
    tips, owners = [], []
    for stroke, part in zip(sample.strokes, sample.stroke_parts, strict=True):
        if part != SHELL_RIM:
            continue
        for tip in (np.asarray(stroke[0], float), np.asarray(stroke[-1], float)):
            i = int(np.argmin(np.linalg.norm(here_px - tip, axis=1)))
            if np.linalg.norm(tip - here_px[i]) <= 4.0 * sigma:
                tips.append(tip)
                owners.append(i)
    info = float(sum(slope[i] @ slope[i] for i in owners))
    if not tips or info == 0:
        return None
    t_ml = float(
        sum(slope[i] @ (tip - base[i]) for tip, i in zip(tips, owners, strict=True)) / info
    )
    sd = float(sigma / np.sqrt(info))

    lo, hi = (v * DIAG for v in SHELL_T)
    grid = decision_grid(t_ml, sd)
    grid = grid[(grid >= lo) & (grid <= hi)]  # the prior's support
    truth = _volume(context, op, op.t)
    t_best, p_best = best_decision(grid, _volumes(context, op, grid), t_ml, sd)
    parts = zip(sample.strokes, sample.stroke_parts, strict=True)
    rim = [np.asarray(s, float) for s, part in parts if part == SHELL_RIM]
    try:  # the project's fitting, told f, from the same rim strokes
        t_fit = shell_fit(context, rf.face, cam, rim).t
    except FitError:
        t_fit = float("nan")
    return ShellBound(
        float(op.t),
        t_ml,
        sd,
        len(tips),
        t_best,
        p_best,
        _passes(context, op, t_ml, truth),
        _passes(context, op, t_best, truth),
        _passes(context, op, t_fit, truth),
    )


def _volume(context, op: Shell, t: float) -> float:
    try:
        return float(apply_operation(context, Shell(op.face, float(t))).Volume())
    except OperationError:
        return float("nan")


def _volumes(context, op: Shell, ts: np.ndarray) -> np.ndarray:
    """The shell's volume at each t of `ts`: a cubic through VOLUME_SAMPLES built ones
    where it fits them, else each built."""
    if len(ts) <= VOLUME_SAMPLES:
        return np.array([_volume(context, op, t) for t in ts])
    knots = np.linspace(ts.min(), ts.max(), VOLUME_SAMPLES)
    built = np.array([_volume(context, op, t) for t in knots])
    if np.isfinite(built).all():
        cubic = np.polyfit(knots, built, 3)
        if np.abs(np.polyval(cubic, knots) - built).max() <= VOLUME_FIT_REL * built.max():
            return np.polyval(cubic, ts)
    return np.array([_volume(context, op, t) for t in ts])


def _passes(context, op: Shell, t: float, truth: float) -> bool:
    v = _volume(context, op, t)
    return bool(np.isfinite(v) and min(v, truth) / max(v, truth) >= RECOVERY_IOU)


def bound_of_set(data: str, limit: int | None = None) -> dict:
    """The bound over a generated set's shells with polygonal rims (the first `limit`
    samples): the oracle's rate, the best decision's rate and its expected rate (the mean
    posterior probability of passing: the bound), with how many samples count of how
    many shells were drawn, the median sd of t relative to t, and the rate of the
    project's fitting told f (`fitting/shell.shell_fit`) on the same samples."""
    rows, drawn = bounds_over_set(data, limit, OperatorType.SHELL, shell_bound)
    return {
        **summary((rows, drawn)),
        "median_sd_over_t": float(np.median([r.sd / r.t_true for r in rows])) if rows else None,
        "fitting_rate": float(np.mean([r.fit_recovered for r in rows])) if rows else None,
    }
