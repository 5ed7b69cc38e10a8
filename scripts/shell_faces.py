# SPDX-License-Identifier: LGPL-2.1-or-later
"""Which faces of the example models a shell can open.

    .bin/python scripts/shell_faces.py [--t 1.5]

Opens each planar, cylindrical and conical face of each example protocol's final solid
(the enclosure's aside: it is built for a shell) with walls t mm thick, and prints per
kind of face how many build and why the others are refused; faces of other kinds
(extruded and revolved Beziers) cannot be a shell's face f at all.
"""

import argparse
from collections import Counter
from pathlib import Path

from Sketch2CADWorkbench.brep.faces import face_ref_at, face_ref_of
from Sketch2CADWorkbench.brep.operators import apply_operation, build
from Sketch2CADWorkbench.brep.protocol import OperationError, Shell, load

ROOT = Path(__file__).resolve().parents[1]


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--t", type=float, default=1.5)
    a = p.parse_args()
    built, refused, why = Counter(), Counter(), Counter()
    for path in sorted((ROOT / "examples" / "protocols").glob("*.json")):
        if path.stem == "enclosure":
            continue
        solid = build(load(path))
        for face in solid.Faces():
            kind = face.geomType().lower()
            if kind not in ("plane", "cylinder", "cone"):
                refused[kind] += 1
                why["not a face a shell opens"] += 1
                continue
            ref = face_ref_of(face) if kind == "plane" else face_ref_at(face, face.Center())
            try:
                apply_operation(solid, Shell(ref, a.t))
                built[kind] += 1
            except OperationError as e:
                refused[kind] += 1
                why[str(e).split(": ", 2)[-1].split(" (")[0].split(";")[0]] += 1
    for kind in sorted(set(built) | set(refused)):
        print(f"{kind}: {built[kind]} built, {refused[kind]} refused")
    for reason, n in why.most_common():
        print(f"  {n:4d}  {reason}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
