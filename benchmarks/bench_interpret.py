# SPDX-License-Identifier: LGPL-2.1-or-later
"""Time of one interpret step on held-out sketches, stage by stage (the requirement:
a median of at most 100 ms on 2 CPU cores).

    .bin/python benchmarks/bench_interpret.py DATA [--limit 100] [--threads 2] [--warmup 3]

Interprets the first LIMIT samples of a generated set (level 1, no regularization, as
`sketch2cad eval --recovery` does) once each, after WARMUP untimed ones, and prints the
median and 90% quantile of each stage `interpret` times itself: render (framing the
strokes and the VTK context maps), networks (classifier and the segmentations of every
operator read), fitting (every face and operator read, regularization, the other
Boolean), B-rep (every Boolean built: the results of the readings fitting keeps, built
while reading to refuse one that fails or changes nothing, and the step's mirror image
or regularized rebuild) and the total. Wall time: other work on the machine inflates
it; say the load beside the figure.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
from pathlib import Path

import numpy as np
import torch
from tqdm import tqdm

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from machine import machine_line

from datagen.dataset import Dataset
from Sketch2CADWorkbench.brep.operators import replay
from Sketch2CADWorkbench.inference.context import InterpretError
from Sketch2CADWorkbench.inference.interpret import interpret
from Sketch2CADWorkbench.inference.options import InterpretOptions
from Sketch2CADWorkbench.inference.weights import load_predictor
from Sketch2CADWorkbench.render.maps import MapRenderer

STAGES = ("render", "networks", "fitting", "brep", "total")


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("data")
    p.add_argument("--limit", type=int, default=100)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--warmup", type=int, default=3)
    a = p.parse_args()
    print(machine_line())
    torch.set_num_threads(a.threads)
    predictor, renderer = load_predictor(), MapRenderer()
    predictor.threads = a.threads  # the predictor sets torch's threads on each pass
    ds = Dataset(a.data)
    n = min(a.limit, len(ds))
    times: dict[str, list[float]] = {k: [] for k in STAGES}
    refused = 0
    for i in tqdm(range(-min(a.warmup, n), n), desc="interpret", unit="step"):
        s = ds.sample(max(i, 0))
        try:
            got = interpret(
                replay(s.context)[-1],
                s.strokes,
                s.camera,
                predictor,
                renderer,
                InterpretOptions(regularize=False),
            )
        except InterpretError:
            refused += i >= 0
            continue
        if i >= 0:
            for k in STAGES:
                times[k].append(got.timings_ms[k])
    print(
        f"{len(times['total'])} steps timed ({refused} refused), {a.threads} torch threads, "
        f"load {os.getloadavg()[0]:.1f}"
    )
    for k in STAGES:
        v = np.array(times[k])
        print(f"  {k:9s} median {statistics.median(v):7.1f} ms   90% {np.quantile(v, 0.9):7.1f} ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
