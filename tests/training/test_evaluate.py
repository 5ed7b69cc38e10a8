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


def test_a_set_with_shells_is_scored_with_the_shipped_four_class_networks(tmp_path):
    """The shipped U-Net and head have no shell class: both are scored on the samples of
    their classes, and the shells are still counted in the set."""
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
    assert result["structured"]["n"] == len(ops) - shells
