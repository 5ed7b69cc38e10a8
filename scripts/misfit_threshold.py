# SPDX-License-Identifier: LGPL-2.1-or-later
"""How well a reading's own sketch explains real strokes, and scribbles: the data behind
interpret's doubt thresholds (readings past them are flagged as doubtful).

    .bin/python scripts/misfit_threshold.py DATA [--skip K] [--limit N] [--scribbles 300]
        [--scribble-seed 0] [--features OUT.json] [--choose]
    .bin/python scripts/misfit_threshold.py --from FEATURES.json [MORE.json ...] [--choose]
    .bin/python scripts/misfit_threshold.py --from FEATURES.json [...] --recovery DATA
        [--skip K] [--control-seed 0]

Interprets every sample of a held-out generated set (level 1) and random scribbles over
random boxes (or reads what an earlier run wrote with --features), and records for each
accepted reading its doubt measures (`reading.doubt_measures`): how far the strokes lie
from the operation's own sketch and the sketch from the strokes, and the classifier's
confidence. It prints the shares of
real sketches and of scribbles that the shipped rule (`reading.doubts`) flags, and
with --choose the rule (one or two measures, thresholds at high quantiles of the real
ones) that lets the fewest scribbles through while flagging at most 1% of the real
sketches. Choose on one set, report on another (another datagen seed and
--scribble-seed).

With --recovery DATA (the set the --from files were made of, in their order, from sample
--skip on) it lists the real sketches the shipped rule flags and reads them again, with
as many unflagged ones drawn at random as a control, as `sketch2cad eval --recovery`
does (the same interpret() call, volume IoU with the ground truth's result, misread
below training.recovery.RECOVERY_IOU): are the flagged sketches the misread ones?
"""

import argparse
import json
import sys
from itertools import combinations, product
from pathlib import Path

import numpy as np
from tqdm import tqdm

from datagen.dataset import Dataset
from datagen.sequences import random_box
from datagen.views import view_direction
from Sketch2CADWorkbench.brep.faces import OperationError
from Sketch2CADWorkbench.brep.operators import make_box, replay
from Sketch2CADWorkbench.inference.context import InterpretError
from Sketch2CADWorkbench.inference.interpret import interpret
from Sketch2CADWorkbench.inference.options import InterpretOptions
from Sketch2CADWorkbench.inference.reading import DOUBT, DOUBT_MEASURES, doubts
from Sketch2CADWorkbench.inference.weights import load_predictor
from Sketch2CADWorkbench.render.frustum import fit_camera
from Sketch2CADWorkbench.render.maps import MapRenderer

# Thresholds tried: these quantiles of the real sketches' measures (low ones for the
# confidence); a rule may flag at most MAX_REAL_FLAGGED of the real sketches.
QUANTILES = (0.99, 0.9925, 0.995, 0.9975, 1.0)
MAX_REAL_FLAGGED = 0.01


def fits_of_samples(data: str, predictor, renderer, limit: int, skip: int = 0) -> list:
    out = []
    ds = Dataset(data)
    bar = tqdm(total=min(limit, max(len(ds) - skip, 0)), desc="held-out", unit="sample")
    seen = 0
    for k in ds.shards:
        for s in ds.samples(k):
            seen += 1
            if seen <= skip:
                continue
            if len(out) >= limit:
                return out
            bar.update(1)
            try:
                got = interpret(
                    replay(s.context)[-1],
                    s.strokes,
                    s.camera,
                    predictor,
                    renderer,
                    InterpretOptions(regularize=False),
                )
                out.append(got.measures())
            except InterpretError:
                out.append(None)
    return out


def fits_of_scribbles(n: int, predictor, renderer, seed: int) -> list:
    rng, out = np.random.default_rng(seed), []
    for _ in tqdm(range(n), desc="scribbles"):
        solid = make_box(random_box(rng))
        cam = fit_camera(solid, view_direction(rng, np.array([0.0, 0.0, 1.0])))
        k = int(rng.integers(1, 9))
        strokes = [
            np.cumsum(rng.normal(0, 6.0, (int(rng.integers(5, 40)), 2)), axis=0)
            + rng.uniform(40, 216, 2)
            for _ in range(k)
        ]
        try:
            out.append(interpret(solid, strokes, cam, predictor, renderer).measures())
        except InterpretError:
            out.append(None)
    return out


def recovery_of_flagged(data: str, real: list, skip: int, seed: int) -> None:
    """Print the flagged real readings (sample indices) and how the flagged ones and an
    equal-size random control of unflagged ones are recovered."""
    from Sketch2CADWorkbench.brep.compare import volume_iou
    from Sketch2CADWorkbench.brep.operators import apply_operation
    from training.recovery import RECOVERY_IOU

    flagged = [skip + i for i, f in enumerate(real) if f is not None and doubts(f)]
    unflagged = [skip + i for i, f in enumerate(real) if f is not None and not doubts(f)]
    control = sorted(
        int(i)
        for i in np.random.default_rng(seed).choice(
            unflagged, size=min(len(flagged), len(unflagged)), replace=False
        )
    )
    print(f"flagged samples: {flagged}\ncontrol samples: {control}")
    ds, predictor, renderer = Dataset(data), load_predictor(), MapRenderer()
    for name, indices in (("flagged", flagged), ("control", control)):
        misread = 0
        for i in indices:
            s = ds.sample(i)
            context = replay(s.context)[-1]
            try:
                got = interpret(
                    context,
                    s.strokes,
                    s.camera,
                    predictor,
                    renderer,
                    InterpretOptions(regularize=False),
                )
                iou = volume_iou(got.solid, apply_operation(context, s.operation))
                note = f"IoU {iou:.3f}, flagged now {got.doubtful}"
            except (InterpretError, OperationError) as e:
                iou, note = 0.0, f"failed: {str(e)[:60]}"
            misread += iou < RECOVERY_IOU
            print(f"  {name} {i} ({s.op_type.value}): {note}", flush=True)
        print(f"{name}: {len(indices)}, misread (IoU < {RECOVERY_IOU}) {misread}")


def choose(real: list, scrib: list) -> list:
    """Rules (thresholds by measure) flagging at most MAX_REAL_FLAGGED of the real
    sketches, fewest scribbles read without a flag first: (scribbles passed, real
    flagged, rule)."""
    r = [f for f in real if f is not None]
    s = [f for f in scrib if f is not None]
    options = {}
    for name in DOUBT_MEASURES:
        rv = np.array([f[name] for f in r])
        qs = [1 - q for q in QUANTILES] if name == "confidence" else QUANTILES
        options[name] = sorted({float(np.quantile(rv, q)) for q in qs})

    def flags(f, rule):
        return any(f[k] < v if k == "confidence" else f[k] > v for k, v in rule.items())

    found = []
    for names in [(n,) for n in options] + list(combinations(options, 2)):
        for values in product(*(options[n] for n in names)):
            rule = dict(zip(names, values, strict=False))
            real_flagged = sum(flags(f, rule) for f in r) / len(real)
            if real_flagged <= MAX_REAL_FLAGGED:
                found.append((sum(not flags(f, rule) for f in s) / len(scrib), real_flagged, rule))
    return sorted(found, key=lambda x: (x[0], x[1]))


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("data", nargs="?")
    p.add_argument(
        "--from", dest="features_in", nargs="+", help="--features files to read (and pool) instead"
    )
    p.add_argument("--skip", type=int, default=0, help="leave out the first SKIP samples")
    p.add_argument("--limit", type=int, default=10**9, help="LIMIT samples only")
    p.add_argument("--scribbles", type=int, default=300)
    p.add_argument("--scribble-seed", type=int, default=0)
    p.add_argument("--features", help="also write every reading's measures here (JSON)")
    p.add_argument(
        "--choose",
        action="store_true",
        help="print the rules that flag at most 1%% of the real sketches",
    )
    p.add_argument(
        "--recovery",
        metavar="DATA",
        help="with --from: read the flagged real sketches of DATA and a control "
        "of unflagged ones again and say which are misread",
    )
    p.add_argument("--control-seed", type=int, default=0)
    a = p.parse_args()
    if a.recovery and not a.features_in:
        p.error("--recovery needs --from")
    if a.features_in:
        saved = [json.loads(Path(f).read_text()) for f in a.features_in]
        real, scrib = ([f for one in saved for f in one[k]] for k in ("real", "scribbles"))
    elif a.data:
        predictor, renderer = load_predictor(), MapRenderer()
        real = fits_of_samples(a.data, predictor, renderer, a.limit, a.skip)
        scrib = fits_of_scribbles(a.scribbles, predictor, renderer, a.scribble_seed)
    else:
        p.error("give a data set or --from")
    if a.features:
        Path(a.features).write_text(
            json.dumps(
                {
                    "real": real,
                    "scribbles": scrib,
                }
            )
        )
    r = [f for f in real if f is not None]
    s = [f for f in scrib if f is not None]
    print(f"real sketches: {len(real)}, read {len(r)}; scribbles: {len(scrib)}, read {len(s)}")
    for name in DOUBT_MEASURES:
        rv = np.array([f[name] for f in r])
        sv = np.array([f[name] for f in s])
        print(
            f"  {name}: real 1/50/99/max {np.quantile(rv, 0.01):.3f} / "
            f"{np.quantile(rv, 0.5):.3f} / {np.quantile(rv, 0.99):.3f} / {rv.max():.3f}; "
            f"scribbles 10/50/90 {np.quantile(sv, 0.1):.3f} / {np.quantile(sv, 0.5):.3f} / "
            f"{np.quantile(sv, 0.9):.3f}"
        )
    if a.choose:
        for passed, flagged, rule in choose(real, scrib)[:5]:
            print(
                f"  rule {rule}: flags {100 * flagged:.2f}% of the real sketches, "
                f"scribbles read without a flag {100 * passed:.1f}%"
            )
    flagged = sum(bool(doubts(f)) for f in r)
    print(
        f"the shipped rule {DOUBT}: flags {flagged} of the {len(r)} real readings "
        f"({100 * flagged / len(real):.1f}% of the real sketches; refused "
        f"{100 * (len(real) - len(r)) / len(real):.1f}%); scribbles read without a flag: "
        f"{sum(not doubts(f) for f in s)} of {len(scrib)} "
        f"({100 * sum(not doubts(f) for f in s) / len(scrib):.1f}%)"
    )
    if a.recovery:
        recovery_of_flagged(a.recovery, real, a.skip, a.control_seed)
    return 0


if __name__ == "__main__":
    sys.exit(main())
