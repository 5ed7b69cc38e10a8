# SPDX-License-Identifier: LGPL-2.1-or-later
"""Scoring the networks on a generated set."""

import subprocess
import sys

import numpy as np

from datagen.dataset import Dataset
from Sketch2CADWorkbench.brep.protocol import OperatorType
from Sketch2CADWorkbench.inference.weights import shipped_head
from Sketch2CADWorkbench.sketch.labels import LABELLED
from training.evaluate import evaluate

CLI = [sys.executable, "-m", "Sketch2CADWorkbench.cli"]


def test_a_set_with_shells_is_scored_by_the_unet_on_its_four_classes_and_the_head_on_five(
    tmp_path,
):
    """The shipped U-Net has no shell class: it is scored on the samples of its four
    classes; the shipped head, which classifies the shell, on every sample."""
    out = subprocess.run(
        [*CLI, "datagen", "--out", str(tmp_path), "--count", "12", "--seed", "4"]
        + ["--noise-level", "1", "--shells", "--workers", "1"],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert out.returncode == 0, out.stderr[-2000:]
    ds = Dataset(tmp_path)
    ops = np.concatenate([ds.shard_arrays(k)["op_type"] for k in ds.shards])
    shells = int((ops == LABELLED.index(OperatorType.SHELL)).sum())
    assert shells > 0, "the seed drew no shell"
    result, _ = evaluate(tmp_path, None, latency_runs=1, head=shipped_head(None))
    assert result["n"] == len(ops) - shells
    assert result["structured"]["n"] == len(ops)
