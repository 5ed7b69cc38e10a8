# SPDX-License-Identifier: LGPL-2.1-or-later
"""Training in two processes (`sketch2cad train --nproc 2`: torchrun, DDP over gloo): a
step's gradient is the single process's with the same global batch, the ranks end with
the same weights, a run trains as one process does, and it resumes from rank 0's
checkpoint."""

import json
import subprocess
import sys
from pathlib import Path

import torch

from datagen.dataset import Dataset
from Sketch2CADWorkbench.cli import main
from Sketch2CADWorkbench.inference.models import (
    Sketch2CADNet,
    class_weights,
    load_checkpoint,
    loss_terms,
)
from training.data import load_pooled
from training.distributed import Ranks, epoch_order

TOLERANCE = 0.15
ARGS = [
    "--batch-size",
    "8",
    "--lr",
    "0.01",
    "--warmup-steps",
    "5",
    "--threads",
    "2",
    "--internal-size",
    "16",
    "--widths",
    "8",
    "16",
    "32",
]


def _train(data, out, *args) -> int:
    return main(["train", "--data", str(data), "--out", str(out), *ARGS, *map(str, args)])


def _events(out):
    return [json.loads(r) for r in (out / "log.jsonl").read_text().splitlines() if '"event"' in r]


def _loss(model, data_dir, out) -> float:
    """The summed losses over the whole tiny set (eval mode, no augmentation)."""
    data = load_pooled(Dataset(data_dir), model, out)
    model.eval()
    with torch.no_grad():
        x, face, curve, mask, op = data.batch(torch.arange(len(data)), "cpu")
        w = class_weights(torch.bincount(op, minlength=4))
        return float(sum(loss_terms(model, model(x), op, face, curve, mask, w)))


def test_the_ranks_deal_out_one_order_as_one_process_takes_it():
    one = epoch_order(10, 7, 3, Ranks())
    assert torch.equal(one, torch.randperm(10, generator=torch.Generator().manual_seed(10)))
    halves = [epoch_order(10, 7, 3, Ranks(r, 2)) for r in (0, 1)]
    # global batch j of 4 = the next 4 of the one order, 2 from each rank
    assert torch.equal(torch.stack(halves, 1).flatten(), one)


def test_a_step_in_two_processes_has_the_gradient_of_one_process(tiny_data, tmp_path):
    # eval mode: batch-norm statistics and dropout masks are each process's own
    step = Path(__file__).with_name("ddp_step.py")
    torchrun = [sys.executable, "-m", "torch.distributed.run", "--standalone", "--nproc_per_node=2"]
    for out, launch in ((tmp_path / "one", []), (tmp_path / "two", torchrun)):
        subprocess.run(
            [*(launch or [sys.executable]), str(step), str(tiny_data), str(out)], check=True
        )
    one, two = (torch.load(tmp_path / d / "step.pt") for d in ("one", "two"))
    assert torch.allclose(one["terms"], two["terms"], rtol=1e-5)
    assert float((one["grad"] - two["grad"]).norm()) < 1e-5 * float(one["grad"].norm())


def test_two_processes_train_as_one_and_resume(tiny_data, tmp_path):
    steps = 30
    assert _train(tiny_data, tmp_path / "one", "--steps", steps) == 0
    assert _train(tiny_data, tmp_path / "two", "--steps", steps, "--nproc", 2) == 0
    starts = [e for e in _events(tmp_path / "two") if e["what"] == "start"]
    assert starts[0]["processes"] == 2 and starts[0]["threads"] == 1
    end = _events(tmp_path / "two")[-1]
    assert end["what"] == "end" and end["step"] == steps
    assert end["rank_weight_spread"] == 0.0  # rank 1 holds exactly rank 0's weights

    one, _ = load_checkpoint(tmp_path / "one" / "sketch2cad_net.pt")
    two, ckpt = load_checkpoint(tmp_path / "two" / "sketch2cad_net.pt")
    assert ckpt["trained_steps"] == steps
    torch.manual_seed(0)
    before = _loss(Sketch2CADNet(one.config), tiny_data, tmp_path)
    l1, l2 = _loss(one, tiny_data, tmp_path), _loss(two, tiny_data, tmp_path)
    # the same descent within TOLERANCE of what it gained (batch-norm statistics and
    # dropout masks are per process, so the runs are not bit-identical)
    assert l1 < 0.9 * before and abs(l2 - l1) < TOLERANCE * (before - l1), (before, l1, l2)

    assert _train(tiny_data, tmp_path / "two", "--steps", steps + 3, "--nproc", 2) == 0
    assert [e["what"] for e in _events(tmp_path / "two")] == ["start", "end", "resume", "end"]
    assert _events(tmp_path / "two")[-1]["step"] == steps + 3


def test_a_batch_that_does_not_divide_among_the_processes_is_refused(tiny_data, tmp_path, capsys):
    assert (
        main(
            [
                "train",
                "--data",
                str(tiny_data),
                "--out",
                str(tmp_path),
                "--nproc",
                "3",
                "--batch-size",
                "8",
            ]
        )
        == 2
    )
    assert "multiple of --nproc 3" in capsys.readouterr().err
    assert not any(tmp_path.iterdir())
