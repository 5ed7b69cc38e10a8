# SPDX-License-Identifier: LGPL-2.1-or-later
"""How many holes drawn as a designer draws them the pipeline reads as that hole.

    .bin/python scripts/hole_rate.py [--count 30] [--seed 17002] [--omit-hidden] [--truth]
                                     [--bosses] [--kind any|hole|notch]

Draws `count` subtract prisms on visible faces of random models through the data
generator's synthesis (tests/inference/holes.py), interprets each with the shipped
networks, with no Boolean chosen and with subtract chosen (the panel's choice), and
prints the share read as the intended hole and what the others became, over all and
for holes wholly on their face and notches (running over its edge) apart, each also
for those drawn with a line besides the rim (a rim alone, the view hiding every side
edge and the floor, does not say how deep the hole is: no reading can recover it);
`--kind` draws only one kind. The holes are
drawn with every line, as the training sketches are; `--omit-hidden` leaves out the lines
the view hides, as a designer drawing only what is seen does. `--truth` runs no
networks: it prints for how many holes the true hole's seen lines explain the strokes
better than those of the boss on its rim that draws the same lines (paper, Fig. 5b).
`--bosses` draws added prisms instead, the other side of the same choice: a rule that
reads more holes must not read bosses as holes.
"""

import argparse
import re
import sys
from collections import Counter
from pathlib import Path

import numpy as np
from tqdm import tqdm

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "inference"))
from holes import KINDS, designer_holes, read_as_the_hole, seen_errors

from Sketch2CADWorkbench.brep.protocol import Mode
from Sketch2CADWorkbench.inference.weights import load_predictor
from Sketch2CADWorkbench.render.maps import MapRenderer


def truth(a: argparse.Namespace) -> int:
    renderer = MapRenderer()
    errors = [
        seen_errors(hole, renderer)
        for hole in tqdm(
            designer_holes(a.count, a.seed, renderer, not a.omit_hidden), total=a.count, unit="hole"
        )
    ]
    pairs = np.array([e for e in errors if e is not None]).reshape(-1, 2)
    closer = int((pairs[:, 0] < pairs[:, 1]).sum())
    print(
        f"{len(pairs)} of {a.count} holes have a boss on their rim that draws the same lines; "
        f"the hole's seen lines lie closer to the strokes for {closer} (median "
        f"{np.median(pairs[:, 0]):.2f} px against the boss's {np.median(pairs[:, 1]):.2f} px)"
    )
    return 0


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--count", type=int, default=30)
    p.add_argument("--seed", type=int, default=17002)
    p.add_argument("--omit-hidden", action="store_true", help="leave out the lines the view hides")
    p.add_argument(
        "--truth",
        action="store_true",
        help="no networks: only whether the true hole's seen lines explain the "
        "strokes better than those of the boss on its rim (paper, Fig. 5b)",
    )
    p.add_argument("--bosses", action="store_true", help="draw bosses (added prisms) instead")
    p.add_argument("--kind", choices=KINDS, default="any", help="holes wholly on f, or notches")
    a = p.parse_args()
    if a.truth:
        return truth(a)
    predictor, renderer = load_predictor(), MapRenderer()
    mode = Mode.ADD if a.bosses else Mode.SUBTRACT
    what = "bosses" if a.bosses else "holes"
    misses = {"no choice": Counter(), f"{mode.value} chosen": Counter()}
    flipped = 0  # read as drawn once the Boolean the reading named is taken
    # per (notch, only those with a depth drawn): how many drawn, and read each way
    kinds = {(notch, depth): Counter() for notch in (False, True) for depth in (False, True)}
    holes = designer_holes(a.count, a.seed, renderer, not a.omit_hidden, mode, a.kind)
    for hole in tqdm(holes, total=a.count, unit=what[:-1]):
        miss, other = read_as_the_hole(hole, predictor, renderer)
        chosen, _ = read_as_the_hole(hole, predictor, renderer, mode)
        read = Counter(
            drawn=1,
            read=not miss,
            flip=not miss or (other is mode and not chosen),
            chosen=not chosen,
        )
        kinds[hole.notch, False].update(read)
        if hole.depth_drawn:
            kinds[hole.notch, True].update(read)
        if miss:
            misses["no choice"][re.sub(r"[0-9.]+", "#", miss.split(":")[0])[:70]] += 1
            flipped += other is mode and not chosen
        if chosen:
            misses[f"{mode.value} chosen"][re.sub(r"[0-9.]+", "#", chosen.split(":")[0])[:70]] += 1
    for how, missed in misses.items():
        read = a.count - sum(missed.values())
        print(
            f"{how}: {what} read as drawn {read} of {a.count} ({100 * read / a.count:.0f}%)"
            + (f"; with the other Boolean it names, {read + flipped}" if how == "no choice" else "")
        )
        for why, n in missed.most_common():
            print(f"  {n} x {why}")
    for (notch, depth), n in kinds.items():
        if n["drawn"]:
            kind = "over the edge of f (notches)" if notch else "wholly on f"
            print(
                ("  of them with a line besides the rim drawn: " if depth else f"{kind}: ")
                + f"{n['drawn']} {what}, read as drawn {n['read']} with no choice, "
                f"{n['flip']} with the other Boolean it names, {n['chosen']} with "
                f"{mode.value} chosen"
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
