# SPDX-License-Identifier: LGPL-2.1-or-later
"""Time of replaying a long protocol: STEPS small square holes cut into the top of a
1000 x 1000 x 20 mm plate, one subtracted prism each, and the seconds of each block of
steps (each step works on a solid with more faces, so the later blocks are slower).

    .bin/python benchmarks/bench_replay.py [--steps 100 200 400] [--block 50] [--profile]

Every stage of a step handles the whole solid: OCCT's Boolean builds the whole result,
unifying its faces looks at every face, and the face a step stands on is found among all
of them; so a step costs time in proportion to the faces (OCCT's Boolean a little more:
the top face holds every hole) and the replay grows with the square of the steps. OCCT's
validity check, whose cost on a face with K holes grows with K^2, runs once, at the end.
`--profile` prints where the time of the first STEPS goes. Wall time: other work on the
machine inflates it; the CPU time less so; the load is printed beside the figures.
"""

from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from Sketch2CADWorkbench.brep.operators import build
from Sketch2CADWorkbench.brep.protocol import (
    AddSubPrism,
    Box,
    FaceRef,
    Mode,
    Protocol,
)

TOP = FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0))
PITCH, HALF, PER_ROW = 20.0, 2.0, 50  # hole centres 20 mm apart, 4 mm wide, 50 a row


def holes(steps: int) -> Protocol:
    """The plate with `steps` square holes, 5 mm deep, row by row."""
    ops = []
    for i in range(steps):
        x = -490.0 + PITCH * (i % PER_ROW)
        y = -490.0 + PITCH * (i // PER_ROW)
        square = tuple(
            (x + sx * HALF, y + sy * HALF, 10.0) for sx, sy in ((-1, -1), (1, -1), (1, 1), (-1, 1))
        )
        ops.append(AddSubPrism(TOP, square, 5.0, Mode.SUBTRACT))
    return Protocol(Box((1000.0, 1000.0, 20.0)), tuple(ops))


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--steps", type=int, nargs="+", default=[100, 200, 400])
    p.add_argument("--block", type=int, default=50)
    p.add_argument("--profile", action="store_true")
    a = p.parse_args()
    if a.profile:
        protocol = holes(a.steps[0])
        profiler = cProfile.Profile()
        profiler.runcall(build, protocol)
        pstats.Stats(profiler).sort_stats("cumulative").print_stats(25)
        return 0
    for steps in a.steps:
        marks, t0, cpu0 = [], time.perf_counter(), time.process_time()

        def mark(i: int, marks: list[float] = marks, cpu0: float = cpu0) -> None:
            if i % a.block == 0:
                marks.append(time.process_time() - cpu0)

        build(holes(steps), on_step=mark)
        wall, cpu = time.perf_counter() - t0, time.process_time() - cpu0
        blocks = [b - a_ for a_, b in zip([0.0] + marks, marks, strict=False)]
        print(
            f"{steps} steps: {wall:.1f} s wall, {cpu:.1f} s CPU (load average "
            f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores); CPU s per {a.block} "
            "steps: " + " ".join(f"{s:.1f}" for s in blocks),
            flush=True,
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
