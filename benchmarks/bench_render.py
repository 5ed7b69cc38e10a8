# SPDX-License-Identifier: LGPL-2.1-or-later
"""Benchmark of the context-map renderer on the example models.

Prints, per example solid, tessellations per second (from scratch: the solid's stored
triangulation is removed first), full map sets (depth, normal, face ID, view depth)
per second from a ready mesh, and both together, at 256 x 256 by default; views are
random directions framing the solid, as in data generation.

Usage: .bin/python benchmarks/bench_render.py [--size 256] [--repeats 20]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from machine import machine_line
from OCP.BRepTools import BRepTools

from Sketch2CADWorkbench.brep.operators import build
from Sketch2CADWorkbench.brep.protocol import load
from Sketch2CADWorkbench.render.frustum import fit_camera
from Sketch2CADWorkbench.render.maps import MapRenderer
from Sketch2CADWorkbench.render.mesh import tessellate

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "protocols"


def _per_second(seconds: list[float]) -> float:
    """Rate from the median time: robust to the other jobs sharing the machine."""
    return 1.0 / float(np.median(seconds))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=256, help="map side in pixels")
    parser.add_argument("--repeats", type=int, default=20, help="timed runs per solid")
    args = parser.parse_args()
    print(machine_line())

    rng = np.random.default_rng(0)
    renderer = MapRenderer()
    print(
        f"{'model':10s} {'faces':>5s} {'tris':>6s} {'tess/s':>8s} {'maps/s':>8s} "
        f"{'both/s':>8s} {'fg %':>5s}"
    )
    totals = {"tess": [], "maps": [], "both": []}
    for path in sorted(EXAMPLES.glob("*.json")):
        solid = build(load(path))
        cams = []
        for _ in range(args.repeats):
            d = rng.normal(size=3)
            d[2] = -abs(d[2])  # from above, as a designer looks
            cams.append(
                fit_camera(
                    solid,
                    tuple(d / np.linalg.norm(d)),
                    (0.0, 0.0, 1.0),
                    rng.uniform(0.8, 1.6),
                    args.size,
                )
            )
        tess, maps, both = [], [], []
        coverage = []
        renderer.render(tessellate(solid), cams[0])  # warm up: shaders, buffers
        for cam in cams:
            BRepTools.Clean_s(solid.wrapped)
            t0 = time.perf_counter()
            mesh = tessellate(solid)
            t1 = time.perf_counter()
            m = renderer.render(mesh, cam)
            t2 = time.perf_counter()
            tess.append(t1 - t0)
            both.append(t2 - t0)
            coverage.append(float((m.face_id >= 0).mean()))
        for cam in cams:  # the same mesh from many views, as the generator's view tries
            t0 = time.perf_counter()
            renderer.render(mesh, cam)
            maps.append(time.perf_counter() - t0)
        totals["tess"] += tess
        totals["maps"] += maps
        totals["both"] += both
        print(
            f"{path.stem:10s} {len(solid.Faces()):5d} {len(mesh.triangles):6d} "
            f"{_per_second(tess):8.1f} {_per_second(maps):8.1f} {_per_second(both):8.1f} "
            f"{100 * np.mean(coverage):5.0f}"
        )
    print(
        f"{'all':10s} {'':5s} {'':6s} {_per_second(totals['tess']):8.1f} "
        f"{_per_second(totals['maps']):8.1f} {_per_second(totals['both']):8.1f}"
    )
    print(
        f"(median rates; maps at {args.size} x {args.size} including read-back and "
        "interpolation; one process)"
    )


if __name__ == "__main__":
    main()
