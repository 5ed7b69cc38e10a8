# SPDX-License-Identifier: LGPL-2.1-or-later
"""How a drilled hole drawn into each face of a box with a boss is read, per face.

    .bin/python scripts/hole_faces.py [--count 20] [--seed 1] [--noise-level 1]
        [--lines all|seen|depth|own] [--turn 8] [--faces -Y +X top]

A cylindrical hole (r 6 mm, 15 deep) into the front (-Y), right (+X) and top face of a
box that had a boss (tests/inference/holes.py, BOSSED_BOX), drawn in FreeCAD's isometric
view turned a little, as a designer draws it: the rim, the depth lines and the bottom
circle where the view sees them (hidden lines left out), each stroke a freehand one of
the data generator's hand. Each drawing is interpreted with the shipped networks and no
Boolean chosen; per face the script prints how many were read as the hole (a
subtraction, volume IoU >= 0.95), as a boss (an addition), as something else, how
many of the misses offer the hole as the alternative reading (one click), and how many
readings carry an alternative at all.
"""

import argparse
import sys
from collections import Counter
from pathlib import Path

from tqdm import tqdm

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "inference"))
from holes import HOLE_CENTRES, LINE_STYLES, gui_holes, read_as_the_hole

from Sketch2CADWorkbench.brep.protocol import Mode
from Sketch2CADWorkbench.inference.weights import load_predictor
from Sketch2CADWorkbench.render.maps import MapRenderer


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--count", type=int, default=20, help="drawings per face")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--noise-level", type=int, default=1, choices=(1, 2, 3))
    p.add_argument(
        "--lines",
        default="seen",
        choices=LINE_STYLES,
        help="every line, what the view sees, or what the hole's own cylinder shows "
        "(tests/inference/holes.py); default seen",
    )
    p.add_argument("--turn", type=float, default=8.0, help="degrees the view turns (default 8)")
    p.add_argument(
        "--faces",
        nargs="+",
        default=list(HOLE_CENTRES),
        choices=list(HOLE_CENTRES),
        help="the faces drilled (default all)",
    )
    a = p.parse_args()
    predictor, renderer = load_predictor(), MapRenderer()
    for face in a.faces:
        got = Counter()
        holes = gui_holes(face, a.count, a.seed, renderer, a.lines, a.noise_level, a.turn)
        for hole in tqdm(holes, total=a.count, desc=face, unit="hole", leave=False):
            miss, other = read_as_the_hole(hole, predictor, renderer)
            kind = "hole" if not miss else "boss" if "(add)" in miss else "other"
            if kind == "other":
                print(f"  {face}: {miss[:100]}")
            got[kind] += 1
            got["offered"] += bool(miss) and other is Mode.SUBTRACT
            got["alternative"] += other is not None
        print(
            f"{face:>4}: read as the hole {got['hole']}/{a.count}, as a boss {got['boss']}, "
            f"other {got['other']}; misses offering the hole as the alternative "
            f"{got['offered']}/{a.count - got['hole']}; readings carrying an alternative "
            f"{got['alternative']}/{a.count}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
