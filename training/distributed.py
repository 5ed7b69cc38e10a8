# SPDX-License-Identifier: LGPL-2.1-or-later
"""Training in several processes: PyTorch's DistributedDataParallel under torchrun
(`sketch2cad train --nproc N`, or `torchrun --nproc_per_node=N -m Sketch2CADWorkbench.cli
train ...`, several machines through torchrun's rendezvous).

torchrun sets WORLD_SIZE, RANK and LOCAL_RANK; `from_environment` joins the process group
(gloo on the CPU, nccl on GPUs). Every process holds the whole pooled data set and the
same model; a DistributedSampler deals each epoch's order out to the ranks, so one step's
global batch is the same samples a single process would take with that batch size, and
DDP averages the gradients. Rank 0 alone validates, logs and writes checkpoints.
"""

from __future__ import annotations

import os
import sys
from dataclasses import dataclass

import torch
import torch.distributed as dist
from torch.nn.parallel import DistributedDataParallel
from torch.utils.data import DistributedSampler


@dataclass(frozen=True)
class Ranks:
    """This process's place in the run: `rank` of `world` processes, `local_rank` on its
    machine (one process, the default, is rank 0 of 1)."""

    rank: int = 0
    world: int = 1
    local_rank: int = 0

    @property
    def main(self) -> bool:
        """Whether this process validates, logs and writes the run's files."""
        return self.rank == 0

    @property
    def distributed(self) -> bool:
        return self.world > 1


def from_environment(device: str) -> Ranks:
    """The ranks torchrun's environment describes, the process group joined (gloo for
    the CPU, nccl for CUDA, this process's GPU its LOCAL_RANK); one process without it."""
    world = int(os.environ.get("WORLD_SIZE", "1"))
    if world <= 1:
        return Ranks()
    local = int(os.environ.get("LOCAL_RANK", "0"))
    if not dist.is_initialized():
        if device == "cuda":
            torch.cuda.set_device(local)
        dist.init_process_group("nccl" if device == "cuda" else "gloo")
    return Ranks(dist.get_rank(), dist.get_world_size(), local)


def close(ranks: Ranks) -> None:
    """Leave the process group (after the last collective call)."""
    if ranks.distributed and dist.is_initialized():
        dist.destroy_process_group()


def exit_worker(code: int) -> None:
    """End a torchrun worker now, skipping the interpreter's finalization. There a gloo
    thread finishing an all-reduce can free a tensor's Python object, wants the GIL, is
    made to exit by Python and aborts the process ("terminate called without an active
    exception", SIGABRT, in about 1 of 3 two-process runs under load; gdb on the core:
    ProcessGroupGloo::runLoop -> ~AsyncAllreduceWork -> decref -> PyThread_exit_thread).
    Everything a run writes is already on disk (atomic, fsynced writes)."""
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


def barrier(ranks: Ranks) -> None:
    if ranks.distributed:
        dist.barrier()


def wrap(model: torch.nn.Module, ranks: Ranks, device: str) -> torch.nn.Module:
    """The module to run forward passes through: DDP (gradients averaged over the ranks
    in backward, buffers such as batch-norm statistics sent from rank 0) or the model."""
    if not ranks.distributed:
        return model
    return DistributedDataParallel(
        model, device_ids=[ranks.local_rank] if device == "cuda" else None
    )


def epoch_order(n: int, seed: int, epoch: int, ranks: Ranks) -> torch.Tensor:
    """This rank's share of the epoch's order of n samples: a DistributedSampler's, which
    takes every world-th sample of one seeded permutation from `rank` on (padded to a
    multiple of world); for one process exactly torch.randperm(n) seeded seed + epoch."""
    sampler = DistributedSampler(
        range(n), num_replicas=ranks.world, rank=ranks.rank, shuffle=True, seed=seed
    )
    sampler.set_epoch(epoch)
    return torch.tensor(list(sampler), dtype=torch.int64)


def from_main(value: float, ranks: Ranks, device: str) -> float:
    """Rank 0's `value` on every rank (the elapsed time that sets a --minutes run's
    learning rate and end, which must agree)."""
    if not ranks.distributed:
        return value
    t = torch.tensor([value], dtype=torch.float64, device=device)
    dist.broadcast(t, 0)
    return float(t)


def weighted_mean_share(weights: torch.Tensor, ranks: Ranks) -> torch.Tensor | float:
    """What turns this rank's weighted mean over its samples (sum w l / sum w, the class-
    weighted cross entropy) into its part of the global batch's, given DDP's average
    over the ranks: world * (sum of its w) / (sum of all w). `weights`: its samples' w."""
    if not ranks.distributed:
        return 1.0
    mine = weights.detach().sum()
    total = mine.clone()
    dist.all_reduce(total)
    return ranks.world * mine / total


def mean_over_ranks(values: list[torch.Tensor], ranks: Ranks) -> list[torch.Tensor]:
    """The ranks' average of each (detached) value: with the shares above, the global
    batch's losses, for the log."""
    if not ranks.distributed:
        return values
    t = torch.stack([v.detach() for v in values])
    dist.all_reduce(t)
    return list(t / ranks.world)


def share_buffers(model: torch.nn.Module, ranks: Ranks) -> None:
    """Rank 0's buffers on every rank: DDP sends them before each forward pass, so after
    the last one each rank holds the batch-norm statistics of its own last batch."""
    if ranks.distributed:
        for b in model.buffers():
            dist.broadcast(b.data, 0)


def weight_spread(model: torch.nn.Module, ranks: Ranks, device: str) -> float:
    """The largest difference between the ranks' checksums of every parameter and buffer
    (per tensor: the sum and a position-weighted sum, in float64): 0.0 exactly when the
    processes hold the same weights, as DDP should keep them; 0.0 for one process."""
    if not ranks.distributed:
        return 0.0
    sums = []
    for t in list(model.parameters()) + list(model.buffers()):
        flat = t.detach().to(device, torch.float64).flatten()
        sums += [
            flat.sum(),
            (flat * torch.arange(1, len(flat) + 1, device=device, dtype=torch.float64)).sum(),
        ]
    mine = torch.stack(sums)
    every = [torch.empty_like(mine) for _ in range(ranks.world)]
    dist.all_gather(every, mine)
    return max(float((e - mine).abs().max()) for e in every)
