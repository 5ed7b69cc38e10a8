# SPDX-License-Identifier: LGPL-2.1-or-later
"""How far a reading's own sketch lies from real strokes, and from scribbles: the data
behind interpret.SKETCH_MISFIT_PX (readings past it are flagged as doubtful).

    .bin/python scripts/misfit_threshold.py DATA [--scribbles 300] [--quantile 0.99]

Interprets every sample of a held-out generated set (level 1) and random scribbles over
random boxes, and prints the misfit (px) quantiles of the accepted readings of each, the
threshold at the quantile of the real ones, the share of real sketches it refuses, and
the share of scribbles still accepted.
"""
import argparse
import sys
from pathlib import Path

import numpy as np
from tqdm import tqdm

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "fuzz"))
from datagen.dataset import Dataset  # noqa: E402
from datagen.sequences import random_box  # noqa: E402
from datagen.views import view_direction  # noqa: E402
from Sketch2CADWorkbench.brep.operators import make_box, replay  # noqa: E402
from Sketch2CADWorkbench.inference.interpret import InterpretError, InterpretOptions, interpret  # noqa: E402
from Sketch2CADWorkbench.inference.weights import load_predictor  # noqa: E402
from Sketch2CADWorkbench.render.frustum import fit_camera  # noqa: E402
from Sketch2CADWorkbench.render.maps import MapRenderer  # noqa: E402


def misfits_of_samples(data: str, predictor, renderer) -> list:
    out = []
    ds = Dataset(data)
    for k in tqdm(ds.shards, desc="held-out", unit="shard"):
        for s in ds.samples(k):
            try:
                got = interpret(replay(s.context)[-1], s.strokes, s.camera, predictor, renderer,
                                InterpretOptions(regularize=False))
                out.append(got.misfit_px)
            except InterpretError:
                out.append(None)
    return out


def misfits_of_scribbles(n: int, predictor, renderer, seed: int = 0) -> list:
    rng, out = np.random.default_rng(seed), []
    for _ in tqdm(range(n), desc="scribbles"):
        solid = make_box(random_box(rng))
        cam = fit_camera(solid, view_direction(rng, np.array([0.0, 0.0, 1.0])))
        k = int(rng.integers(1, 9))
        strokes = [np.cumsum(rng.normal(0, 6.0, (int(rng.integers(5, 40)), 2)), axis=0)
                   + rng.uniform(40, 216, 2) for _ in range(k)]
        try:
            out.append(interpret(solid, strokes, cam, predictor, renderer).misfit_px)
        except InterpretError:
            out.append(None)
    return out


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("data")
    p.add_argument("--scribbles", type=int, default=300)
    p.add_argument("--quantile", type=float, default=0.99)
    a = p.parse_args()
    predictor, renderer = load_predictor(), MapRenderer()
    real = misfits_of_samples(a.data, predictor, renderer)
    scrib = misfits_of_scribbles(a.scribbles, predictor, renderer)
    r = np.array([m for m in real if m is not None])
    s = np.array([m for m in scrib if m is not None])
    th = float(np.quantile(r, a.quantile))
    print(f"real sketches: {len(real)}, read {len(r)}; misfit px quantiles 50/90/99/max: "
          f"{np.quantile(r, 0.5):.2f} / {np.quantile(r, 0.9):.2f} / {np.quantile(r, 0.99):.2f}"
          f" / {r.max():.2f}")
    if len(s):
        print(f"scribbles: {len(scrib)}, read {len(s)}; misfit px quantiles 50/90: "
              f"{np.quantile(s, 0.5):.2f} / {np.quantile(s, 0.9):.2f}")
    print(f"threshold at the {a.quantile:.0%} quantile of the real ones: {th:.2f} px: flags "
          f"{100 * (r > th).sum() / len(real):.1f}% of the real sketches read; scribbles read "
          f"without a flag {100 * (s <= th).sum() / len(scrib):.1f}% (read at all: "
          f"{100 * len(s) / len(scrib):.1f}%)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
