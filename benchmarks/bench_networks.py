# SPDX-License-Identifier: LGPL-2.1-or-later
"""Speed of the networks on this machine: training time per sample and inference latency.

    .bin/python benchmarks/bench_networks.py                  # the shipped config
    .bin/python benchmarks/bench_networks.py --candidates     # the design alternatives
    .bin/python benchmarks/bench_networks.py --weights DIR    # a trained model's latency
    .bin/python benchmarks/bench_networks.py --head RUN --data DIR   # with the head, by stage

Training: one optimizer step (forward, the paper's losses at 256 x 256, backward, AdamW)
on random batches, in ms per sample: the median and, as the figure least disturbed by
other work on a shared machine, the minimum over the timed steps. Latency: `predict` on
one full-size sketch (pooling, network, upsampling of all outputs to 256 x 256), median
over runs, at `--infer-threads` threads (2: the target is <= 50 ms per sketch on 2 CPU
cores). Timings are wall time, so other work on the machine inflates them; the median damps that.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import torch

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from machine import machine_line

from Sketch2CADWorkbench.inference.models import (
    N_OPS,
    ModelConfig,
    Sketch2CADNet,
    class_weights,
    count_parameters,
    flops_per_sample,
    load_checkpoint,
    loss_terms,
)

CANDIDATES = {
    "128 / 8..128 (shipped)": ModelConfig(),
    "96 / 8..128": ModelConfig(internal_size=96, widths=(8, 16, 32, 64, 128)),
    "128 / 12..192": ModelConfig(widths=(12, 24, 48, 96, 192)),
    "128 / 16..256": ModelConfig(widths=(16, 32, 64, 128, 256)),
    "256 / 8..128": ModelConfig(internal_size=256, widths=(8, 16, 32, 64, 128)),
}


def random_batch(cfg: ModelConfig, n: int, gen: torch.Generator):
    s = cfg.image_size
    x = torch.rand(n, 5, s, s, generator=gen)
    x[:, 0] = (x[:, 0] > 0.99).float()
    mask = x[:, 0].clone()
    face = (torch.rand(n, s, s, generator=gen) > 0.7).float()
    curve = torch.randint(0, 3, (n, s, s), generator=gen).float() * mask
    op = torch.randint(0, N_OPS, (n,), generator=gen)
    return x, face, curve, mask, op


def train_ms_per_sample(
    cfg: ModelConfig, batch: int, steps: int, threads: int
) -> tuple[float, float]:
    """Median and minimum ms per sample of a training step."""
    torch.set_num_threads(threads)
    gen = torch.Generator().manual_seed(0)
    model = Sketch2CADNet(cfg).train()
    opt = torch.optim.AdamW(model.parameters(), lr=1e-3)
    weights = class_weights(torch.tensor([1, 1, 4, 2]))
    x, face, curve, mask, op = random_batch(cfg, batch, gen)
    xp = model.pool(x)
    times = []
    for i in range(steps + 1):  # the first step warms up the allocator
        t = time.perf_counter()
        out = model(xp)
        loss = sum(loss_terms(model, out, op, face, curve, mask, weights))
        opt.zero_grad(set_to_none=True)
        loss.backward()
        opt.step()
        if i:
            times.append(time.perf_counter() - t)
    return 1e3 * statistics.median(times) / batch, 1e3 * min(times) / batch


def latency_ms(model: Sketch2CADNet, runs: int, threads: int) -> float:
    """Median ms of `predict` on one full-size sketch."""
    torch.set_num_threads(threads)
    s = model.config.image_size
    x = torch.rand(1, 5, s, s)
    x[:, 0] = (x[:, 0] > 0.99).float()
    model.predict(x)
    times = []
    for _ in range(runs):
        t = time.perf_counter()
        model.predict(x)
        times.append(time.perf_counter() - t)
    return 1e3 * statistics.median(times)


def head_latency_ms(
    head: Path, weights: Path | None, data: Path, runs: int, threads: int
) -> dict[str, float]:
    """Median ms per sketch on the first `runs` sketches of a data set (real strokes and
    face maps): the U-Net's predict alone ("unet"), the whole structured predictor
    (observe, classify, segment for the likeliest operator: "unet + head"), and its
    stages: the U-Net's feature maps, the tokens, the head, the decoding and painting."""
    from datagen.dataset import Dataset
    from Sketch2CADWorkbench.inference.head.model import collate
    from Sketch2CADWorkbench.inference.head.paint import painted
    from Sketch2CADWorkbench.inference.head.predictor import load_structured_predictor
    from Sketch2CADWorkbench.inference.head.tokens import feature_maps, tokens
    from Sketch2CADWorkbench.inference.weights import HEAD_NAME
    from Sketch2CADWorkbench.sketch.labels import LABELLED

    torch.set_num_threads(threads)
    p = load_structured_predictor(head / HEAD_NAME if head.is_dir() else head, weights)
    p.threads = threads  # the predictor sets its own thread count on every sketch
    ds = Dataset(data)
    times: dict[str, list[float]] = {}
    for k in range(min(runs + 1, len(ds))):
        s = ds.sample(k)
        x = s.inputs()
        clock = [time.perf_counter()]

        def lap(name, clock=clock, k=k):
            clock.append(time.perf_counter())
            if k:  # the first sketch allocates
                times.setdefault(name, []).append(clock[-1] - clock[-2])

        p.model.predict(torch.from_numpy(x)[None])
        lap("unet")
        p.observe(s.strokes, s.face_id)
        probs = p.classify(x)
        p.segment(x, LABELLED[int(probs.argmax())])
        lap("unet + head")
        with torch.inference_mode():
            u = feature_maps(p.model, torch.from_numpy(x)[None])
            lap("features")
            t = tokens(u.logits[0], u.sketch(0), s.strokes, s.face_id)
            lap("tokens")
            _, roles, faces = p.head(*collate([t]))
            lap("head")
            op = int(probs.argmax())
            painted(roles[0], faces[0], op, s.strokes, t, s.face_id)
            lap("decode + paint")
    return {name: 1e3 * statistics.median(v) for name, v in times.items()}


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--candidates", action="store_true", help="time the design alternatives")
    p.add_argument("--weights", type=Path, help="time this checkpoint's model (latency only)")
    p.add_argument("--batch", type=int, default=16)
    p.add_argument("--steps", type=int, default=5, help="timed training steps per config")
    p.add_argument("--runs", type=int, default=30, help="timed inference runs")
    p.add_argument("--train-threads", type=int, nargs="+", default=[1, 2])
    p.add_argument("--infer-threads", type=int, default=2)
    p.add_argument("--head", type=Path, help="time the structured head (with --data)")
    p.add_argument("--data", type=Path, help="sketches for --head")
    args = p.parse_args()
    print(machine_line())
    if args.head:
        if not args.data:
            p.error("--head needs --data (real strokes and face maps)")
        ms = head_latency_ms(args.head, args.weights, args.data, args.runs, args.infer_threads)
        print(
            f"latency median per sketch ({args.infer_threads} threads, {args.runs} sketches of "
            f"{args.data}): U-Net predict {ms.pop('unet'):.1f} ms; U-Net + head "
            f"{ms.pop('unet + head'):.1f} ms ("
            + ", ".join(f"{k} {v:.1f}" for k, v in ms.items())
            + " ms)"
        )
        return 0
    if args.weights:
        path = args.weights / "sketch2cad_net.pt" if args.weights.is_dir() else args.weights
        model, _ = load_checkpoint(path)
        print(
            f"{path}: latency {latency_ms(model, args.runs, args.infer_threads):.1f} ms "
            f"median per sketch (batch 1, {args.infer_threads} threads)"
        )
        return 0
    configs = CANDIDATES if args.candidates else {"shipped": ModelConfig()}
    head = "".join(f"  train ms/sample {t} thr (min)" for t in args.train_threads)
    print(f"{'config (I / widths)':26s} {'params':>8s} {'MMAC':>7s}{head}  latency ms")
    for name, cfg in configs.items():
        model = Sketch2CADNet(cfg)
        train = "".join(
            "{:22.1f} ({:5.1f})".format(*train_ms_per_sample(cfg, args.batch, args.steps, t))
            for t in args.train_threads
        )
        print(
            f"{name:26s} {count_parameters(model):8d} {flops_per_sample(cfg) / 1e6:7.0f}"
            f"{train}  {latency_ms(model, args.runs, args.infer_threads):10.1f}",
            flush=True,
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
