# SPDX-License-Identifier: LGPL-2.1-or-later
"""Training the networks (`sketch2cad train`), on the data pooled in memory (data.py). A
held-out tail of the data set (whole contexts) gives validation metrics after every
epoch. The learning rate warms up, then follows a cosine over the budget: `--minutes` of
wall time (default; adapts to a busy machine) or `--steps` (exactly reproducible for a
given machine and thread count).

As nanoGPT keeps them apart: `lr_at` is the schedule, `validate` the held-out losses and
metrics, `Run` the run's state and files (opening, resuming, checkpoints, the log),
`train_step` one optimiser step, and `train` the loop (epochs, logging, interruption).

Run folder:
    checkpoint.pt       everything needed to resume (written every few minutes and at
                        the end; a rerun with the same --out resumes from it)
    sketch2cad_net.pt   the final weights with their config (what `eval` and the
                        workbench load; copy it to inference/weights/ to ship it)
    log.jsonl           one JSON object per line: "train" rows (losses, learning rate,
                        speed), "val" rows (per-epoch metrics), "event" rows
    loss_curves.png     training and validation curves
    data-cache-I.pt     the pooled data set

In several processes (torchrun, `--nproc N`: distributed.py) each process takes its share
of every global batch of batch_size samples; rank 0 alone writes these files.
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import numpy as np
import torch
from tqdm import tqdm

from datagen.dataset import Dataset
from Sketch2CADWorkbench.inference.models import (
    N_OPS,
    ModelConfig,
    Sketch2CADNet,
    class_weights,
    load_checkpoint,
    loss_terms,
    save_checkpoint,
)

from . import distributed
from .data import PooledData, data_key, load_pooled, split
from .distributed import Ranks
from .metrics import Tally, curve_hits, face_overlap
from .report import plot_curves


@dataclass
class TrainSettings:
    """Training settings (the command line overrides them; saved in the checkpoint)."""

    minutes: float = 105.0  # wall-time budget of the optimisation loop (validation
    # included, data loading not): fits 2 h with loading
    steps: int = 0  # > 0: a step budget instead (reproducible schedule)
    batch_size: int = 16
    lr: float = 2e-3  # AdamW peak learning rate
    final_lr_fraction: float = 0.02
    warmup_steps: int = 200
    weight_decay: float = 1e-4
    grad_clip: float = 5.0  # max gradient norm: insurance against a bad batch
    val_fraction: float = 0.04  # held-out tail of the data set (whole contexts)
    face_dice: float = 1.0  # weight of the soft Dice term on F (models.loss_terms)
    flip: bool = True  # random horizontal mirror images (N_x negated)
    seed: int = 0
    checkpoint_minutes: float = 5.0
    log_every: int = 25  # steps between "train" log rows
    threads: int = 0  # CPU threads for torch (0: torch's default)
    device: str = "cpu"
    model: ModelConfig = field(default_factory=ModelConfig)


# ---------------------------------------------------------------- validation (estimate_loss)
@torch.no_grad()
def validate(
    model: Sketch2CADNet,
    data: PooledData,
    device: str,
    weights: torch.Tensor,
    face_dice: float = 0.0,
    batch: int = 64,
) -> dict:
    """Losses and the evaluation metrics (evaluate.py) on held-out samples."""
    model.eval()
    tally = Tally()
    losses = np.zeros(3)
    for i in range(0, len(data), batch):
        idx = torch.arange(i, min(i + batch, len(data)))
        x, face, curve, mask, op = data.batch(idx, device)
        out = model(x)
        losses += len(idx) * np.array(
            [float(t) for t in loss_terms(model, out, op, face, curve, mask, weights, face_dice)]
        )
        pick = op[:, None, None, None].expand(-1, 1, *out[1].shape[2:])
        maps = model.upsample(torch.cat([out[1].gather(1, pick), out[2].gather(1, pick)], 1))
        tally.add(
            op,
            out[0].argmax(1),
            data.noise[idx],
            *face_overlap(maps[:, 0].sigmoid(), face),
            *curve_hits(maps[:, 1], curve, mask, op),
        )
    model.train()
    n = max(len(data), 1)
    return {"cls": losses[0] / n, "face": losses[1] / n, "curve": losses[2] / n, **tally.summary()}


# ---------------------------------------------------------------- schedule
def lr_at(s: TrainSettings, step: int, progress: float) -> float:
    """Linear warmup over warmup_steps, then a cosine from lr down to final_lr_fraction lr
    over the budget (progress 0..1)."""
    floor = s.lr * s.final_lr_fraction
    cosine = floor + (s.lr - floor) * 0.5 * (1 + math.cos(math.pi * min(progress, 1.0)))
    return cosine * min(1.0, (step + 1) / s.warmup_steps)


# ---------------------------------------------------------------- the run
class Run:
    """A training run in its folder: the model, optimizer, data and counters the loop
    advances, and the log and checkpoint it leaves (module docstring).

    Attributes:
        s: the settings (the architecture is the checkpoint's on a resume).
        state: "step", "epoch", "pos" (samples of this epoch done) and "elapsed" (s of
            the loop): all that a resume restores besides the weights and the optimizer.
        resumed: whether it started from out/checkpoint.pt.
    """

    def __init__(self, data_dir: Path, out: Path, settings: TrainSettings, ranks: Ranks = Ranks()):
        """Open the run: resume from out/checkpoint.pt if there is one, else start anew.

        Raises:
            FileNotFoundError: no data set at data_dir.
            ValueError: the data set is empty, the checkpoint belongs to another data set
                or map size, or the batch does not divide among the processes.
        """
        s = settings
        if s.batch_size % ranks.world:
            raise ValueError(
                f"--batch-size {s.batch_size} does not divide among {ranks.world} processes"
            )
        self.ranks = ranks
        if s.threads:
            torch.set_num_threads(s.threads)
        out.mkdir(parents=True, exist_ok=True)
        self.out, self.ckpt_path, self.log_path = out, out / "checkpoint.pt", out / "log.jsonl"
        self.ds = ds = Dataset(data_dir)
        if len(ds) == 0:
            raise ValueError(f"{data_dir}: the data set has no complete shard yet")
        ckpt = None
        if self.ckpt_path.exists():
            model, ckpt = load_checkpoint(self.ckpt_path)
            s = _resumed_settings(s, model, ckpt, ds, self.ckpt_path)
        else:
            # a new model takes the data set's map size
            s = replace(
                s, model=replace(s.model, image_size=int(ds.manifest.get("image_size", 256)))
            )
            torch.manual_seed(s.seed)
            model = Sketch2CADNet(s.model)
        size = int(ds.manifest.get("image_size", model.config.image_size))
        if size != model.config.image_size:
            raise ValueError(
                f"{data_dir} holds {size} x {size} maps, but the model in "
                f"{self.ckpt_path} takes {model.config.image_size} x "
                f"{model.config.image_size}"
            )
        self.s, self.model, self.resumed = s, model, ckpt is not None
        model.to(s.device).train()
        self.net = distributed.wrap(model, ranks, s.device)  # what forward passes go through

        t_load = time.perf_counter()
        if ranks.local_rank:  # one process per machine pools the data set into the cache
            distributed.barrier(ranks)
        data = load_pooled(ds, model, out)
        if ranks.distributed and not ranks.local_rank:
            distributed.barrier(ranks)
        self.load_s = time.perf_counter() - t_load
        tr_idx, va_idx = split(len(data), s.val_fraction, int(ds.manifest.get("per_context", 4)))
        self.train_data, self.val_data = data.subset(tr_idx), data.subset(va_idx)
        self.counts = torch.bincount(self.train_data.op, minlength=N_OPS)
        self.weights = class_weights(self.counts).to(s.device)
        self.n = len(self.train_data)

        self.opt = torch.optim.AdamW(model.parameters(), lr=s.lr, weight_decay=s.weight_decay)
        self.state = {"step": 0, "epoch": 0, "pos": 0, "elapsed": 0.0}
        if ckpt is not None:
            self.opt.load_state_dict(ckpt["optimizer"])
            self.state = dict(ckpt["state"])
            torch.set_rng_state(ckpt["rng"])
        elif ranks.main:
            self.log_path.write_text("")
        # open for the run's life (close() closes it)
        self.log = open(self.log_path, "a") if ranks.main else None  # noqa: SIM115

    def write(self, row: dict) -> None:
        """One row of log.jsonl, flushed at once (rank 0's only)."""
        if self.log is None:
            return
        self.log.write(json.dumps(row) + "\n")
        self.log.flush()

    def progress(self) -> float:
        """How much of the budget is spent (0..1): steps, or minutes of the loop."""
        s = self.s
        return self.state["step"] / s.steps if s.steps else self.state["elapsed"] / (60 * s.minutes)

    def order(self, epoch: int) -> torch.Tensor:
        """This process's share of the epoch's order of the training samples (seeded by
        the epoch)."""
        return distributed.epoch_order(self.n, self.s.seed * 1000, epoch, self.ranks)

    def next_batch(self, perm: torch.Tensor) -> torch.Tensor:
        """This process's samples of the next global batch (state["pos"] counts the
        epoch's samples over all processes)."""
        mine = self.state["pos"] // self.ranks.world
        return perm[mine : mine + self.s.batch_size // self.ranks.world]

    def flips(self, count: int) -> torch.Tensor | None:
        """Which of the step's samples are mirrored (seeded by the step), or None; the
        global batch's draws dealt out as its samples are."""
        if not self.s.flip:
            return None
        w = self.ranks.world
        return (
            torch.rand(
                count * w,
                generator=torch.Generator().manual_seed(self.s.seed * 1000003 + self.state["step"]),
            )[self.ranks.rank :: w]
            < 0.5
        )

    def save(self, rng: torch.Tensor) -> None:
        """The checkpoint (with the torch RNG state `rng` to resume from) and the curves
        (rank 0's)."""
        if not self.ranks.main:
            return
        save_checkpoint(
            self.ckpt_path,
            self.model,
            optimizer=self.opt.state_dict(),
            state=dict(self.state),
            settings=asdict(self.s),
            data_key=data_key(self.ds, self.model.config),
            class_counts=self.counts.tolist(),
            rng=rng,
        )
        plot_curves(self.log_path, self.out / "loss_curves.png", self.s.face_dice)

    def validation(self) -> dict | None:
        """The validation metrics now, logged (None without validation samples, and on
        ranks other than 0)."""
        if not len(self.val_data) or not self.ranks.main:
            return None
        v = validate(self.model, self.val_data, self.s.device, self.weights, self.s.face_dice)
        self.write(
            {
                "kind": "val",
                "step": self.state["step"],
                "epoch": self.state["epoch"],
                "elapsed_s": round(self.state["elapsed"], 1),
                **v,
            }
        )
        return v

    def finish(self) -> Path:
        """Validate, checkpoint, and write the final weights; close the log (rank 0; the
        other ranks only check that they hold the same weights)."""
        s, state = self.s, self.state
        distributed.share_buffers(self.model, self.ranks)
        spread = distributed.weight_spread(self.model, self.ranks, s.device)
        final = self.out / "sketch2cad_net.pt"
        if not self.ranks.main:
            return final
        v = self.validation()
        self.save(torch.get_rng_state())
        self.model.cpu()
        save_checkpoint(
            final,
            self.model,
            class_counts=self.counts.tolist(),
            trained_steps=state["step"],
            trained_epochs=state["epoch"] + state["pos"] / self.n,
            trained_minutes=state["elapsed"] / 60,
            settings=asdict(s),
            data_key=data_key(self.ds, self.model.config),
            validation=v,
        )
        self.write(
            {
                "kind": "event",
                "what": "end",
                "step": state["step"],
                "elapsed_s": round(state["elapsed"], 1),
                "rank_weight_spread": spread,
            }
        )
        self.log.close()
        return final


def _resumed_settings(
    s: TrainSettings, model: Sketch2CADNet, ckpt: dict, ds: Dataset, ckpt_path: Path
) -> TrainSettings:
    """The settings of a resumed run: the checkpoint's architecture; say which of the
    other settings changed. Raises ValueError for a checkpoint of another data set."""
    saved = ckpt["settings"]
    s = replace(s, model=model.config)  # the architecture is the checkpoint's
    if ckpt["data_key"] != data_key(ds, model.config):
        raise ValueError(
            f"{ckpt_path} was trained on another data set "
            f"({ckpt['data_key']}); use a new --out folder"
        )
    for name in ("batch_size", "lr", "seed", "val_fraction", "flip"):
        if getattr(s, name) != saved[name]:
            print(f"train: resuming with {name}={getattr(s, name)} (checkpoint had {saved[name]})")
    return s


# ---------------------------------------------------------------- one step
def train_step(run: Run, idx: torch.Tensor) -> list[torch.Tensor]:
    """One optimiser step on the training samples `idx`, at the scheduled learning rate;
    returns the loss terms (classification, face, curve). Counters are not advanced."""
    s = run.s
    flip = run.flips(len(idx))
    for g in run.opt.param_groups:
        g["lr"] = lr_at(s, run.state["step"], run.progress())
    x, face, curve, mask, op = run.train_data.batch(idx, s.device, flip)
    cls, *rest = loss_terms(run.model, run.net(x), op, face, curve, mask, run.weights, s.face_dice)
    # in several processes, as one: the weighted mean over the whole global batch
    terms = [cls * distributed.weighted_mean_share(run.weights[op], run.ranks), *rest]
    run.opt.zero_grad(set_to_none=True)
    sum(terms).backward()
    torch.nn.utils.clip_grad_norm_(run.model.parameters(), s.grad_clip)
    return distributed.mean_over_ranks(terms, run.ranks)


# ---------------------------------------------------------------- the loop
def train(data_dir: Path, out: Path, settings: TrainSettings) -> Path:
    """Train, or resume from out/checkpoint.pt, until the budget is spent.

    Every epoch ends in validation; a "train" log row every log_every steps; a checkpoint
    every checkpoint_minutes. Ctrl-C saves a checkpoint that resumes exactly (unless it
    came while the optimizer was updating the weights: then the last one is kept).

    Returns:
        the path of the final weights (out/sketch2cad_net.pt).
    Raises:
        FileNotFoundError: no data set at data_dir.
        ValueError: the checkpoint belongs to another data set or model config.

    Under torchrun (WORLD_SIZE set) each process runs this, joined in one process group.
    """
    ranks = distributed.from_environment(settings.device)
    try:
        return _loop(Run(data_dir, out, settings, ranks))
    finally:
        distributed.close(ranks)


def _loop(run: Run) -> Path:
    s, state, n, main = run.s, run.state, run.n, run.ranks.main
    run.write(
        {
            "kind": "event",
            "what": "resume" if run.resumed else "start",
            "step": state["step"],
            "train_samples": n,
            "val_samples": len(run.val_data),
            "class_counts": run.counts.tolist(),
            "load_s": round(run.load_s, 1),
            "settings": asdict(s),
            "threads": torch.get_num_threads(),
            "processes": run.ranks.world,
        }
    )
    if main:
        print(
            f"train: {n} training / {len(run.val_data)} validation samples (pooled in "
            f"{run.load_s:.0f} s); class counts {run.counts.tolist()}; "
            f"{torch.get_num_threads()} threads"
            + (f" in each of {run.ranks.world} processes" if run.ranks.distributed else "")
            + (f"; resuming at step {state['step']}" if run.resumed else "")
        )

    perm = run.order(state["epoch"])
    total = s.steps if s.steps else int(60 * s.minutes)
    bar = tqdm(
        total=total,
        unit="step" if s.steps else "s",
        desc="train",
        dynamic_ncols=True,
        disable=not main,
    )
    bar.update(state["step"] if s.steps else int(state["elapsed"]))
    t0 = time.perf_counter() - state["elapsed"]
    last_save = time.perf_counter()
    sums, seen, t_log = np.zeros(3), 0, time.perf_counter()
    stepping, rng, buffers = False, torch.get_rng_state(), []
    try:
        while run.progress() < 1.0:
            # what an interrupted step must start from again: its forward pass draws
            # dropout masks and moves the batch-norm statistics (a few hundred numbers)
            rng, buffers = torch.get_rng_state(), [b.clone() for b in run.model.buffers()]
            if state["pos"] >= n:  # end of an epoch: validate and reshuffle
                state["epoch"] += 1
                state["pos"] = 0
                perm = run.order(state["epoch"])
                v = run.validation()
                if v:
                    bar.write(
                        f"epoch {state['epoch']}: val acc "
                        f"{v['classification_accuracy']:.4f}, face IoU "
                        + " ".join(
                            f"{k[:2]} {d['face_iou']:.3f}"
                            for k, d in v["per_operator"].items()
                            if d["n"]
                        )
                    )
            idx = run.next_batch(perm)
            terms = train_step(run, idx)
            stepping = True
            run.opt.step()
            state["step"] += 1
            state["pos"] += len(idx) * run.ranks.world
            stepping = False

            sums += [t.item() for t in terms]
            seen += 1
            now = time.perf_counter()
            # the processes must agree on a --minutes run's schedule and end: rank 0's clock
            state["elapsed"] = (
                now - t0 if s.steps else distributed.from_main(now - t0, run.ranks, s.device)
            )
            if state["step"] % s.log_every == 0:
                c, f, cu = sums / seen
                run.write(
                    {
                        "kind": "train",
                        "step": state["step"],
                        "epoch": state["epoch"],
                        "samples": state["step"] * s.batch_size,
                        "cls": c,
                        "face": f,
                        "curve": cu,
                        "loss": c + f + cu,
                        "lr": run.opt.param_groups[0]["lr"],
                        "elapsed_s": round(state["elapsed"], 1),
                        "ms_per_sample": 1e3 * (now - t_log) / (seen * s.batch_size),
                    }
                )
                bar.set_postfix(
                    cls=f"{c:.3f}", face=f"{f:.4f}", curve=f"{cu:.3f}", epoch=state["epoch"]
                )
                sums, seen, t_log = np.zeros(3), 0, now
            bar.update(1 if s.steps else int(state["elapsed"]) - bar.n)
            if now - last_save > 60 * s.checkpoint_minutes:
                run.save(torch.get_rng_state())
                run.write({"kind": "event", "what": "checkpoint", "step": state["step"]})
                last_save = time.perf_counter()
    except KeyboardInterrupt:
        bar.close()
        if not stepping:  # else the weights may be half updated: keep the last checkpoint
            with torch.no_grad():
                for b, saved in zip(run.model.buffers(), buffers, strict=True):
                    b.copy_(saved)
            run.save(rng)
            run.write({"kind": "event", "what": "interrupted", "step": state["step"]})
            if main:
                print(
                    f"train: interrupted at step {state['step']}; checkpoint saved, run "
                    "the same command again to resume"
                )
        if run.log:
            run.log.close()
        raise
    bar.close()

    final = run.finish()
    if main:
        print(
            f"train: {state['step']} steps = {state['epoch'] + state['pos'] / n:.2f} epochs "
            f"of {n} samples in {state['elapsed'] / 60:.1f} min; weights {final}"
        )
    return final
