# SPDX-License-Identifier: LGPL-2.1-or-later
"""How many shells, and how many subtracted prisms beside them, the pipeline reads as drawn.

    .bin/python scripts/shell_rate.py [--count 20] [--seed 44001] [--noise-level 1]

Draws `count` shells and `count` subtracted prisms on random models through the data
generator (`sample_on`, its hand at the given noise level, a line down a wall in some
shells' sketches), interprets each with the shipped networks, regularization off, and
prints for each kind the share recovered (volume IoU >= 0.95 with the truth) and what
the others were read as: the shell must not take a prism's sketch, nor a prism a shell's.
"""

import argparse
from collections import Counter

import numpy as np
from tqdm import tqdm

from datagen.generate import Context, sample_on
from datagen.sequences import sample_sequence
from Sketch2CADWorkbench.brep.compare import volume_iou
from Sketch2CADWorkbench.brep.operators import apply_operation, build
from Sketch2CADWorkbench.brep.protocol import Mode, OperatorType
from Sketch2CADWorkbench.inference.context import InterpretError
from Sketch2CADWorkbench.inference.interpret import interpret
from Sketch2CADWorkbench.inference.options import InterpretOptions
from Sketch2CADWorkbench.inference.weights import load_predictor
from Sketch2CADWorkbench.render.maps import MapRenderer

RECOVERY_IOU = 0.95


def samples(kind: OperatorType, a: argparse.Namespace, renderer: MapRenderer):
    """`a.count` samples of `kind` (prisms: subtracted ones only), on contexts of 0 to 3
    operations."""
    n, k = 0, 0
    while n < a.count:
        rng = np.random.default_rng([a.seed, list(OperatorType).index(kind), k])
        k += 1
        s = sample_on(Context(sample_sequence(rng, k % 4)), rng, a.noise_level, renderer, kind=kind)
        if kind is OperatorType.ADDSUB and s.operation.mode is not Mode.SUBTRACT:
            continue
        n += 1
        yield s


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--count", type=int, default=20)
    p.add_argument("--seed", type=int, default=44001)
    p.add_argument("--noise-level", type=int, default=1, choices=(1, 2, 3))
    a = p.parse_args()
    renderer, predictor = MapRenderer(), load_predictor()
    options = InterpretOptions(regularize=False)
    for kind in (OperatorType.SHELL, OperatorType.ADDSUB):
        read, walls, recovered = Counter(), 0, 0
        for s in tqdm(samples(kind, a, renderer), total=a.count, unit=kind.value):
            context = build(s.context)
            truth = apply_operation(context, s.operation)
            walls += 0 in s.stroke_parts and kind is OperatorType.SHELL
            try:
                got = interpret(context, s.strokes, s.camera, predictor, renderer, options)
            except InterpretError:
                read["nothing"] += 1
                continue
            read[got.op_type.value] += 1
            recovered += volume_iou(got.solid, truth) >= RECOVERY_IOU
        name = "shells" if kind is OperatorType.SHELL else "subtracted prisms"
        extra = f" ({walls} with a line down a wall)" if kind is OperatorType.SHELL else ""
        print(
            f"{name}{extra}: {recovered} of {a.count} recovered (IoU >= {RECOVERY_IOU}); "
            f"read as {dict(read)}"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
