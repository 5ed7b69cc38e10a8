# SPDX-License-Identifier: LGPL-2.1-or-later
"""Training the network: `sketch2cad train --data DIR --out DIR [--device cpu|cuda]`.

The whole data set is pooled to the network's internal resolution once and held in
memory; training runs for a time budget with a cosine learning rate, checkpoints every
few minutes, and resumes from out/checkpoint.pt when run again.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import torch
from tqdm import tqdm

from ..datagen.dataset import Dataset
from .models import (N_OPS, NetConfig, Sketch2CADNet, class_weights, load_model, loss_terms,
                     pool_inputs, pool_labels, save_checkpoint)

# Settings (plain values; the command line overrides the first four).
MINUTES = 100.0          # training time budget
BATCH = 32
LR = 2e-3
VAL_FRACTION = 0.03      # held-out shards for per-epoch validation
SEED = 0
CHECKPOINT_EVERY_S = 300
LOG_EVERY = 20           # steps
WEIGHT_DECAY = 1e-4


@dataclass
class Tensors:
    """A data set pooled to the internal resolution (first axis = sample)."""

    x: torch.Tensor      # (N, 5, I, I) float16
    face: torch.Tensor   # (N, I, I) float16
    curve: torch.Tensor  # (N, I, I) uint8
    mask: torch.Tensor   # (N, I, I) uint8
    op: torch.Tensor     # (N,) int64

    def batch(self, idx, device) -> tuple[torch.Tensor, ...]:
        return (self.x[idx].to(device).float(), self.face[idx].to(device).float(),
                self.curve[idx].to(device).float(), self.mask[idx].to(device).float(),
                self.op[idx].to(device))


def load_tensors(ds: Dataset, shards: list[int], k: int, desc: str) -> Tensors:
    """Shards of a data set as pooled tensors."""
    parts = []
    for s in tqdm(shards, desc=desc, unit="shard", leave=False):
        b = ds.batch(s)
        x = pool_inputs(torch.from_numpy(b.inputs), k).half()
        f, c, m = pool_labels(torch.from_numpy(b.face_label), torch.from_numpy(b.curve_label),
                              torch.from_numpy(b.stroke_mask), k)
        parts.append((x, f.half(), c.to(torch.uint8), m.to(torch.uint8),
                      torch.from_numpy(b.op_type)))
    return Tensors(*[torch.cat([p[i] for p in parts]) for i in range(5)])


def split_shards(ds: Dataset) -> tuple[list[int], list[int]]:
    """Training and validation shards (the last few shards are held out)."""
    n_val = max(1, int(round(len(ds.shards) * VAL_FRACTION))) if len(ds.shards) > 1 else 0
    return ds.shards[:len(ds.shards) - n_val], ds.shards[len(ds.shards) - n_val:]


@torch.no_grad()
def validate(model: Sketch2CADNet, data: Tensors, device, weights) -> dict[str, float]:
    """Mean losses and accuracies on pooled validation data."""
    model.eval()
    sums = {"cls": 0.0, "face": 0.0, "curve": 0.0, "acc": 0.0}
    n = len(data.op)
    for i in range(0, n, 64):
        idx = torch.arange(i, min(i + 64, n))
        x, f, c, m, op = data.batch(idx, device)
        logits, fl, cc = model(x)
        a, b, d = loss_terms(logits, fl, cc, op, f, c, m, weights)
        k = len(idx)
        sums["cls"] += float(a) * k
        sums["face"] += float(b) * k
        sums["curve"] += float(d) * k
        sums["acc"] += float((logits.argmax(1) == op).float().sum())
    model.train()
    return {k: v / max(n, 1) for k, v in sums.items()}


def plot_curves(log_path: Path, out_png: Path) -> None:
    """Loss curves (training per logged step, validation per epoch) as a PNG."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = [json.loads(l) for l in log_path.read_text().splitlines() if l.strip()]
    tr = [r for r in rows if r["kind"] == "train"]
    va = [r for r in rows if r["kind"] == "val"]
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.6))
    for ax, key, title in zip(axes, ("cls", "face", "curve"),
                              ("classification (weighted CE)", "base face (MSE)",
                               "curve on strokes (MSE)")):
        ax.plot([r["step"] for r in tr], [r[key] for r in tr], lw=0.8, label="train")
        if va:
            ax.plot([r["step"] for r in va], [r[key] for r in va], "o-", label="validation")
        ax.set_title(title)
        ax.set_xlabel("step")
        ax.set_yscale("log")
        ax.grid(alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(out_png, dpi=90)
    plt.close(fig)


def train(data_dir: Path, out: Path, device: str, minutes: float, batch: int = BATCH,
          lr: float = LR, threads: int | None = None) -> Path:
    """Train (or resume) within `minutes` of wall time; returns the final weights' path."""
    torch.manual_seed(SEED)
    if threads:
        torch.set_num_threads(threads)
    out.mkdir(parents=True, exist_ok=True)
    ckpt_path, log_path = out / "checkpoint.pt", out / "log.jsonl"
    ds = Dataset(data_dir)
    tr_shards, va_shards = split_shards(ds)
    cfg = NetConfig()
    k = cfg.size // cfg.internal
    train_data = load_tensors(ds, tr_shards, k, "loading training shards")
    val_data = load_tensors(ds, va_shards, k, "loading validation shards") if va_shards else None
    counts = torch.bincount(train_data.op, minlength=N_OPS)
    weights = class_weights(counts).to(device)
    state = {"step": 0, "elapsed": 0.0, "epoch": 0}
    if ckpt_path.exists():
        model, ckpt = load_model(ckpt_path)
        state = ckpt["state"]
        print(f"train: resuming from {ckpt_path} at step {state['step']}, "
              f"{state['elapsed'] / 60:.1f} min done")
    else:
        model = Sketch2CADNet(cfg)
        log_path.write_text("")
    model.to(device).train()
    opt = torch.optim.AdamW(model.parameters(), lr=lr, weight_decay=WEIGHT_DECAY)
    if ckpt_path.exists():
        opt.load_state_dict(ckpt["optimizer"])
    budget = minutes * 60.0
    n = len(train_data.op)
    gen = torch.Generator().manual_seed(SEED + state["epoch"])
    order = torch.randperm(n, generator=gen)
    pos = state.get("pos", 0)
    start = time.perf_counter() - state["elapsed"]
    last_ckpt = time.perf_counter()

    def save():
        state["elapsed"] = time.perf_counter() - start
        save_checkpoint(ckpt_path, model, {"optimizer": opt.state_dict(), "state": dict(state),
                                           "class_counts": counts.tolist(),
                                           "data": str(data_dir)})
        plot_curves(log_path, out / "loss_curves.png")

    bar = tqdm(total=int(budget), initial=int(state["elapsed"]), unit="s", desc="train")
    with open(log_path, "a") as log:
        while time.perf_counter() - start < budget:
            if pos >= n:  # epoch end: validate, reshuffle
                state["epoch"] += 1
                pos = 0
                order = torch.randperm(n, generator=torch.Generator().manual_seed(
                    SEED + state["epoch"]))
                if val_data is not None:
                    v = validate(model, val_data, device, weights)
                    log.write(json.dumps({"kind": "val", "step": state["step"],
                                          "epoch": state["epoch"], **v}) + "\n")
                    log.flush()
                    bar.write(f"epoch {state['epoch']}: val acc {v['acc']:.4f} face "
                              f"{v['face']:.4f} curve {v['curve']:.4f}")
            idx = order[pos:pos + batch]
            pos += batch
            state["pos"] = pos
            frac = min((time.perf_counter() - start) / budget, 1.0)
            for g in opt.param_groups:  # cosine decay over the time budget
                g["lr"] = lr * 0.5 * (1 + math.cos(math.pi * frac))
            x, f, c, m, op = train_data.batch(idx, device)
            logits, fl, cc = model(x)
            a, b, d = loss_terms(logits, fl, cc, op, f, c, m, weights)
            loss = a + b + d
            opt.zero_grad(set_to_none=True)
            loss.backward()
            opt.step()
            state["step"] += 1
            if state["step"] % LOG_EVERY == 0:
                log.write(json.dumps({"kind": "train", "step": state["step"],
                                      "epoch": state["epoch"], "cls": float(a),
                                      "face": float(b), "curve": float(d),
                                      "lr": opt.param_groups[0]["lr"],
                                      "time": time.perf_counter() - start}) + "\n")
                log.flush()
                bar.set_postfix(cls=f"{float(a):.3f}", face=f"{float(b):.4f}",
                                curve=f"{float(d):.3f}")
            bar.n = int(min(time.perf_counter() - start, budget))
            bar.refresh()
            if time.perf_counter() - last_ckpt > CHECKPOINT_EVERY_S:
                save()
                last_ckpt = time.perf_counter()
        if val_data is not None:
            v = validate(model, val_data, device, weights)
            log.write(json.dumps({"kind": "val", "step": state["step"], "epoch": state["epoch"],
                                  **v}) + "\n")
    bar.close()
    save()
    final = out / "sketch2cad_net.pt"
    save_checkpoint(final, model.cpu(), {"class_counts": counts.tolist(),
                                         "trained_steps": state["step"],
                                         "trained_minutes": state["elapsed"] / 60,
                                         "samples": n, "data": str(data_dir)})
    print(f"train: {state['step']} steps ({state['step'] * batch / max(n, 1):.1f} epochs of "
          f"{n} samples) in {state['elapsed'] / 60:.1f} min; weights {final}")
    return final


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("train", help="train the networks on a generated data set",
                       description="Train (or resume) the classifier/segmentation network.")
    p.add_argument("--data", type=Path, required=True, help="data set folder (sketch2cad datagen)")
    p.add_argument("--out", type=Path, required=True, help="run folder: checkpoints, log, curves")
    p.add_argument("--device", default="cuda" if torch.cuda.is_available() else "cpu",
                   choices=["cpu", "cuda"])
    p.add_argument("--minutes", type=float, default=MINUTES, help=f"time budget (default {MINUTES})")
    p.add_argument("--batch", type=int, default=BATCH)
    p.add_argument("--lr", type=float, default=LR)
    p.add_argument("--threads", type=int, help="CPU threads for torch")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if args.device == "cuda" and not torch.cuda.is_available():
        print("sketch2cad train: error: --device cuda but no CUDA device is available",
              file=sys.stderr)
        return 2
    try:
        train(args.data, args.out, args.device, args.minutes, args.batch, args.lr, args.threads)
    except (FileNotFoundError, ValueError) as e:
        print(f"sketch2cad train: error: {e}", file=sys.stderr)
        return 2
    return 0

