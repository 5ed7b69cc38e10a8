# SPDX-License-Identifier: LGPL-2.1-or-later
"""Benchmark of reading stroke roles from geometry (fitting/stroke_roles.py) for many
strokes: the cost must grow about linearly with their number.

Usage: .bin/python benchmarks/bench_stroke_roles.py [--counts 1000 3000 10000] [--seed 0]
    [--roles OUT.json]

Each sketch is many short strokes over the top face of a box seen from above at an
angle (800 x 600): random walks, with a third of them straight strokes along the
image of the face's normal (side-edge candidates, so the grouping of alike chords has
work to do) and some closed loops. Prints the seconds for the readings the pipeline
asks for (a prism at each chord tolerance, with and without the side count, and a
sweep). --roles writes every reading, to compare two versions' readings.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from Sketch2CADWorkbench.brep.faces import FaceFrame, resolve_face
from Sketch2CADWorkbench.brep.operators import make_box
from Sketch2CADWorkbench.brep.protocol import Box, FaceRef
from Sketch2CADWorkbench.inference.fitting.common import FitError
from Sketch2CADWorkbench.inference.fitting.stroke_roles import (
    PRISM_CHORD_TOLERANCES,
    normal_image,
    stroke_roles,
)
from Sketch2CADWorkbench.render.camera import OrthoCamera


def sketch(n: int, rng: np.random.Generator, n2: np.ndarray) -> list[np.ndarray]:
    out = []
    for k in range(n):
        start = rng.uniform((50, 50), (750, 550))
        if k % 3 == 0:  # along n_f's image, a side-edge candidate
            length = rng.uniform(10, 40)
            t = np.linspace(0, 1, 6)[:, None]
            out.append(start + t * length * (n2 + rng.normal(0, 0.05, 2)))
        elif k % 10 == 1:  # a small closed loop
            a = np.linspace(0, 2 * np.pi, 12)
            out.append(start + rng.uniform(5, 15) * np.stack([np.cos(a), np.sin(a)], 1))
        else:
            out.append(start + np.cumsum(rng.normal(0, 4.0, (int(rng.integers(3, 8)), 2)), 0))
    return out


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--counts", type=int, nargs="+", default=[1000, 3000, 10000])
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--roles", help="write every reading here (JSON)")
    a = p.parse_args()
    solid = make_box(Box((40, 30, 20)))
    d = np.array([0.6, 0.9, -1.2])
    cam = OrthoCamera((0.0, 0.0, 5.0), tuple(d / np.linalg.norm(d)), (0, 0, 1), 45.0, 800, 600)
    frame = FaceFrame.of(resolve_face(solid, FaceRef((0, 0, 10), (0, 0, 1))).face)
    n2 = normal_image(cam, frame)
    readings = {}
    for n in a.counts:
        strokes = sketch(n, np.random.default_rng(a.seed), n2)
        t0 = time.perf_counter()
        got = []
        for prism, tol, sides in [
            (True, tol, sides) for tol in PRISM_CHORD_TOLERANCES for sides in (None, n // 3)
        ] + [(False, None, None)]:
            try:
                got.append(stroke_roles(strokes, frame, cam, prism, tol, sides))
            except FitError as e:
                got.append(str(e))
        seconds = time.perf_counter() - t0
        readings[n] = got
        print(
            f"{n} strokes: {seconds:.2f} s for {len(got)} readings "
            f"({1e3 * seconds / len(got):.0f} ms each)",
            flush=True,
        )
    if a.roles:
        Path(a.roles).write_text(json.dumps(readings))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
