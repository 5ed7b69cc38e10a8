# SPDX-License-Identifier: LGPL-2.1-or-later
"""Run by test_distributed.py, once alone and once under torchrun: one training step of a
tiny model in eval mode (no batch-norm batch statistics, no dropout, which are each
process's own), saving rank 0's loss terms and gradient to OUT.

Usage: [torchrun --nproc_per_node=N] ddp_step.py DATA OUT
"""

import sys
from pathlib import Path

import torch

from Sketch2CADWorkbench.inference.models import ModelConfig
from training import distributed
from training.train import Run, TrainSettings, train_step


def main(data: Path, out: Path) -> None:
    settings = TrainSettings(
        steps=1,
        batch_size=16,
        threads=1,
        flip=True,
        model=ModelConfig(internal_size=16, widths=(8, 16, 32)),
    )
    ranks = distributed.from_environment("cpu")
    try:
        run = Run(data, out, settings, ranks)
        run.model.eval()
        terms = train_step(run, run.next_batch(run.order(0)))
        if ranks.main:
            torch.save(
                {
                    "terms": torch.stack([t.detach() for t in terms]),
                    "grad": torch.cat([p.grad.flatten() for p in run.model.parameters()]),
                },
                out / "step.pt",
            )
    finally:
        distributed.close(ranks)


if __name__ == "__main__":
    main(Path(sys.argv[1]), Path(sys.argv[2]))
    distributed.exit_worker(0)  # as the train command's workers end
