# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad datagen`: generate a data set in parallel, deterministically, resumably."""
from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import sys
import time
from pathlib import Path

import numpy as np
from tqdm import tqdm

from .dataset import FORMAT, VERSION, Dataset, shard_complete, shard_name, write_shard
from .generate import IMAGE_SIZE, PER_CONTEXT, generate_block

SHARD_SIZE = 128  # a multiple of PER_CONTEXT: shards hold whole blocks


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("datagen", help="generate synthetic training/evaluation samples",
                       description="Random modeling sequences rendered as sketches over their "
                                   "context, with labels (paper, Sec. 5).")
    p.add_argument("--out", type=Path, required=True, help="data set folder")
    p.add_argument("--count", type=int, required=True, help="number of samples")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--noise-level", default="1", choices=["1", "2", "3", "mix"],
                   help="stroke noise: 1.4%%, 2.8%%, 4.1%% of the image diagonal, or mix "
                        "(the levels cycle per context; default 1)")
    p.add_argument("--workers", type=int, default=2, help="processes (default 2)")
    p.add_argument("--shard-size", type=int, default=SHARD_SIZE,
                   help=f"samples per shard, a multiple of {PER_CONTEXT} (default {SHARD_SIZE})")
    p.add_argument("--preview", type=Path, help="write a contact sheet of the first samples")
    p.set_defaults(func=run)


def noise_of_block(noise: str, block: int) -> int:
    return 1 + block % 3 if noise == "mix" else int(noise)


def _make_shard(job: tuple) -> int:
    folder, seed, k, count, noise, shard_size = job
    from ..render.maps import MapRenderer  # one offscreen window per worker process
    global _RENDERER
    if "_RENDERER" not in globals():
        _RENDERER = MapRenderer()
    first = k * shard_size
    samples = []
    for block in range(first // PER_CONTEXT, (first + count + PER_CONTEXT - 1) // PER_CONTEXT):
        samples += generate_block(seed, block, noise_of_block(noise, block), _RENDERER)
    write_shard(Path(folder), k, samples[:count])
    return count


def run(args: argparse.Namespace) -> int:
    if args.count <= 0:
        print("sketch2cad datagen: error: --count must be positive", file=sys.stderr)
        return 2
    size = args.shard_size
    if size <= 0 or size % PER_CONTEXT:
        print(f"sketch2cad datagen: error: --shard-size must be a positive multiple of "
              f"{PER_CONTEXT}", file=sys.stderr)
        return 2
    out: Path = args.out
    out.mkdir(parents=True, exist_ok=True)
    n_shards = (args.count + size - 1) // size
    manifest = {"format": FORMAT, "version": VERSION, "count": args.count, "seed": args.seed,
                "noise": args.noise_level, "image_size": IMAGE_SIZE, "shard_size": size,
                "per_context": PER_CONTEXT,
                "shards": [f"{shard_name(k)}.npz" for k in range(n_shards)]}
    mpath = out / "manifest.json"
    if mpath.exists():
        old = json.loads(mpath.read_text())
        keys = ("count", "seed", "noise", "shard_size")
        if {k: old.get(k) for k in keys} != {k: manifest[k] for k in keys}:
            print(f"sketch2cad datagen: error: {out} holds a different data set "
                  f"(count/seed/noise {old.get('count')}/{old.get('seed')}/{old.get('noise')}); "
                  "use another --out", file=sys.stderr)
            return 2
    mpath.write_text(json.dumps(manifest, indent=1))
    jobs = [(str(out), args.seed, k, min(size, args.count - k * size), args.noise_level, size)
            for k in range(n_shards) if not shard_complete(out, k)]
    done = args.count - sum(j[3] for j in jobs)
    start = time.perf_counter()
    with tqdm(total=args.count, initial=done, unit="sample", desc="datagen") as bar:
        if args.workers <= 1:
            for j in jobs:
                bar.update(_make_shard(j))
        else:
            ctx = mp.get_context("spawn")  # fresh processes: VTK/OCCT state is not forked
            with ctx.Pool(args.workers) as pool:
                for n in pool.imap_unordered(_make_shard, jobs):
                    bar.update(n)
    made = args.count - done
    secs = time.perf_counter() - start
    if made:
        print(f"datagen: {made} samples in {secs:.0f} s = {made / secs:.2f} samples/s "
              f"with {args.workers} worker(s); {args.count} in {out}")
    if args.preview:
        write_preview(Dataset(out), args.preview)
        print(f"datagen: preview written to {args.preview}")
    return 0


def overlay(sample) -> np.ndarray:
    """A picture of a sample: depth-shaded context, base face tinted, strokes coloured by
    their curve label (start/offset red... see LABEL_COLOURS)."""
    shade = (40 + 180 * sample.depth) * (sample.depth > 0) + 255 * (sample.depth == 0)
    img = np.repeat(shade[..., None], 3, axis=2)
    face = sample.face_label > 0
    img[face] = 0.55 * img[face] + 0.45 * np.array([90, 150, 230])
    mask = sample.stroke_mask > 0
    for label, colour in LABEL_COLOURS.items():
        img[mask & (sample.curve_label == label)] = colour
    return img.astype(np.uint8)


LABEL_COLOURS = {0: (220, 50, 40), 1: (30, 160, 60), 2: (140, 50, 200)}


def write_preview(ds: Dataset, path: Path, count: int = 24) -> None:
    """A contact sheet: sketch over context, base face in blue, curve labels 0/1/2 in
    red/green/purple, captioned with the operator and the noise level."""
    from ..render.picture import contact_sheet, write_png
    samples = []
    for k in ds.shards:
        samples += ds.samples(k)
        if len(samples) >= count:
            break
    samples = samples[:count]
    write_png(contact_sheet([overlay(s) for s in samples], 6,
                            [f"{s.op_type.value} (noise {s.noise_level})" for s in samples]),
              path)
