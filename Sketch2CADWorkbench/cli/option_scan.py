# SPDX-License-Identifier: LGPL-2.1-or-later
"""How often would the other Boolean be named, and how many wrong options would that cover?

`sketch2cad option-scan DATA [addsub|sweep]`: fits every prism (or sweep) of a generated
set from its ground-truth segmentation (the fitting stage alone, `recovery.read_step`),
then, for thresholds 0.25 / 0.5 / 0.75 / 0.9 on the share of the fitted primitive's far
outline that back-projects onto f, prints the share of steps it would be named for and
how many of the steps with the wrong +/- option it would cover. The pipeline names it
when the forced flip would be accepted (`other_option_fits`: 0.25, MOSTLY_FRACTION, or
the outline's region covering half of f).
"""

from __future__ import annotations

import argparse

import numpy as np

from datagen.dataset import Dataset
from training.recovery import read_step

from ..brep.faces import OperationError, resolve_face
from ..brep.operators import replay
from ..brep.protocol import OperatorType
from ..inference.context import InterpretError
from ..inference.fitting.primitive import far_outline_share
from ..inference.options import InterpretOptions


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("data")
    p.add_argument("operator", nargs="?", default="addsub", choices=["addsub", "sweep"])


def run(args: argparse.Namespace) -> int:
    want = OperatorType(args.operator)
    shares, wrong = [], []
    ds = Dataset(args.data)
    for k in ds.shards:
        for s in ds.samples(k):
            if s.op_type is not want:
                continue
            context = replay(s.context)[-1]
            try:
                op = read_step(s, context, None, None, InterpretOptions(regularize=False)).operation
            except (InterpretError, OperationError):
                continue
            face = resolve_face(context, op.face).face
            shares.append(far_outline_share(face, s.camera, op))
            wrong.append(op.mode is not s.operation.mode)
    shares, wrong = np.array(shares), np.array(wrong)
    print(f"{len(shares)} {want.value} steps fitted, {int(wrong.sum())} with the wrong option")
    for th in (0.25, 0.5, 0.75, 0.9):
        named = shares >= th
        print(
            f"  threshold {th:.2f}: named for {100 * named.mean():.0f}% of steps, covers "
            f"{int((named & wrong).sum())} of {int(wrong.sum())} wrong options"
        )
    return 0
