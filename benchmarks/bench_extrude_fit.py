# SPDX-License-Identifier: LGPL-2.1-or-later
"""Time and peak memory of reading one extrusion sketch, by the view's resolution.

Usage: .bin/python benchmarks/bench_extrude_fit.py [--sizes 800x600 4096x4096 8192x8192]

For each size, a fresh process draws a 9 mm extrusion of a 40 x 30 x 20 box's top in
a view of that many pixels framing the box (level-1 strokes, datagen's synthesis) and
interprets it with the shipped networks; it prints the seconds of the interpret step
and the process's peak resident memory. The context maps are 256 x 256 whatever the
view, so neither should grow with the view's resolution.
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time


def one(width: int, height: int) -> dict:
    import numpy as np

    from datagen.strokes import sketch_strokes
    from Sketch2CADWorkbench.brep.operators import make_box
    from Sketch2CADWorkbench.brep.protocol import Box, Extrude, FaceRef
    from Sketch2CADWorkbench.inference.interpret import interpret
    from Sketch2CADWorkbench.inference.weights import load_predictor
    from Sketch2CADWorkbench.render.frustum import fit_camera
    from Sketch2CADWorkbench.render.maps import MapRenderer
    from Sketch2CADWorkbench.sketch.curves import operation_curves

    box = make_box(Box((40, 30, 20)))
    op = Extrude(FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0)), 9.0)
    view = fit_camera(box, (0.6, 0.9, -1.2), size=(width, height))
    curves = operation_curves(box, op, np.array(view.direction))
    strokes, _ = sketch_strokes(curves, view, np.random.default_rng(0), 1)
    predictor, renderer = load_predictor(), MapRenderer()
    t0 = time.perf_counter()
    got = interpret(box, strokes, view, predictor, renderer)
    seconds = time.perf_counter() - t0
    return {
        "seconds": seconds,
        "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
        "read": f"{got.op_type.value} d={got.operations[0].d:.2f}",
    }


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sizes", nargs="+", default=["800x600", "4096x4096", "8192x8192"])
    p.add_argument("--one", help=argparse.SUPPRESS)
    a = p.parse_args()
    if a.one:
        print(json.dumps(one(*map(int, a.one.split("x")))))
        return 0
    for size in a.sizes:
        out = subprocess.run(
            [sys.executable, __file__, "--one", size], capture_output=True, text=True, check=True
        )
        r = json.loads(out.stdout.strip().splitlines()[-1])
        print(
            f"{size}: {r['seconds']:.2f} s, peak RSS {r['peak_mb']:.0f} MB, read as {r['read']}",
            flush=True,
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
