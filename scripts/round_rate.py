# SPDX-License-Identifier: LGPL-2.1-or-later
"""How many rounds drawn across an edge the pipeline reads back.

    .bin/python scripts/round_rate.py [--count 40] [--seed 60001] [--noise-level 1]

Draws `count` bevel samples across an edge (`sketch2cad datagen --round-share 1`'s
synthesis, datagen/rounds.py: fillets, chamfers and freeform profiles on rims and
straight edges, along the edge, its chain or its face's outline) and reads each three
ways, regularization off: the fitting alone given the true profile stroke and edge set
(fitting/rounds.round_fits, the nearest edge's reading), and the whole pipeline with the
shipped networks, with the sample's edge set as the panel's choice, as read (the
classifier's operator) and with the operator forced to bevel. A sample is recovered at
volume IoU >= 0.95 with its true result; the script prints the share per way, on rims
and on straight edges.
"""

import argparse
from collections import Counter

import numpy as np
from tqdm import tqdm

from datagen.generate import Context, sample_on
from datagen.sequences import sample_sequence
from Sketch2CADWorkbench.brep.compare import volume_iou
from Sketch2CADWorkbench.brep.faces import resolve_face
from Sketch2CADWorkbench.brep.operators import apply_operation, build
from Sketch2CADWorkbench.brep.protocol import OperatorType
from Sketch2CADWorkbench.brep.rounds import nearest_edge
from Sketch2CADWorkbench.inference.fitting.rounds import round_fits
from Sketch2CADWorkbench.inference.interpret import interpret
from Sketch2CADWorkbench.inference.options import InterpretOptions
from Sketch2CADWorkbench.inference.weights import load_predictor
from Sketch2CADWorkbench.render.maps import MapRenderer
from Sketch2CADWorkbench.sketch.labels import BEVEL_L

RECOVERED = 0.95


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--count", type=int, default=40)
    p.add_argument("--seed", type=int, default=60001)
    p.add_argument("--noise-level", type=int, default=1)
    a = p.parse_args()
    renderer, predictor = MapRenderer(), load_predictor()
    tally: Counter = Counter()
    for i in tqdm(range(a.count), unit="sample"):
        rng = np.random.default_rng([a.seed, i])
        context = Context(sample_sequence(rng, int(rng.integers(0, 4))))
        sample = sample_on(
            context, rng, a.noise_level, renderer, kind=OperatorType.BEVEL, round_share=1.0
        )
        # the sample's own context: sample_on draws another when this one takes none
        solid, truth = build(sample.context), sample.operation
        want = apply_operation(solid, truth)
        edge = nearest_edge(resolve_face(solid, truth.face).face, np.asarray(truth.corner))[0]
        groups = ("rim" if edge.geomType() == "CIRCLE" else "edge", f"along {truth.edges.value}")
        for where in groups:
            tally[(where, "all")] += 1
        strokes, cam = sample.strokes, sample.camera
        profile = strokes[sample.stroke_parts.index(BEVEL_L)]
        others = [s for s in strokes if s is not profile]
        try:
            op = round_fits(solid, cam, profile, truth.edges, others)[0]
            got_it = volume_iou(apply_operation(solid, op), want) >= RECOVERED
            for where in groups:
                tally[(where, "fitting")] += got_it
        except Exception:  # a fit or build refused: not recovered
            pass
        options = InterpretOptions(regularize=False, edges=truth.edges)
        for way, op_type in (("pipeline", None), ("pipeline, bevel", OperatorType.BEVEL)):
            try:
                got = interpret(solid, strokes, cam, predictor, renderer, options, op_type)
                got_it = volume_iou(got.solid, want) >= RECOVERED
                for where in groups:
                    tally[(where, way)] += got_it
            except Exception:  # refused: not recovered
                pass
    for where in sorted(
        {w for w, way in tally if way == "all"}, key=lambda w: w.startswith("along")
    ):
        n = tally[(where, "all")]
        rates = ", ".join(
            f"{way} {tally[(where, way)]}/{n}" for way in ("fitting", "pipeline", "pipeline, bevel")
        )
        print(f"{where} ({n}): recovered (IoU >= {RECOVERED}): {rates}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
