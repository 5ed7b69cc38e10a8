# SPDX-License-Identifier: LGPL-2.1-or-later
"""Training and evaluating the structured heads (inference/head/) on the frozen U-Net.

`extract` runs the U-Net once over a data set and keeps each sample's tokens and targets
(cached in the run folder: the U-Net is frozen, so every epoch reuses them); `train_head`
fits the head, resumable from out/head-checkpoint.pt after every epoch; `evaluate_head`
scores, on a held-out data set, the U-Net's own maps and the head's choices painted back
into F and C with the paper's metrics (training/metrics.py), one Tally each from one
pass of the U-Net (training/evaluate.score, which `sketch2cad eval` runs too), so both
rows of the ablation come from the same samples and the same code.

Losses, each averaged per sample first so that a bevel's 2 strokes weigh as much as an
add/sub's 15: cross-entropy of the class, of each stroke's role under the ground-truth
operator, and of the base face among the sketch's face tokens (the ground-truth
operator's face logits; a sample whose base face is not in view adds none).
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import torch
import torch.nn.functional as F
from tqdm import tqdm

from datagen.dataset import Dataset, decode_inputs
from Sketch2CADWorkbench.brep.files import atomic_path
from Sketch2CADWorkbench.inference.head.checkpoint import load_head, save_head, sha256_of
from Sketch2CADWorkbench.inference.head.model import (
    ROLE_OFFSETS,
    ROLES,
    HeadConfig,
    StructureHead,
    collate,
)
from Sketch2CADWorkbench.inference.head.tokens import Tokens, feature_channels, feature_maps
from Sketch2CADWorkbench.inference.models import Sketch2CADNet
from Sketch2CADWorkbench.inference.weights import HEAD_NAME, load_model, resolve

from .evaluate import batch_tokens, score
from .pieces import sketch_pieces

# What a cached token file holds: 2, the tokens and roles of the pieces of curves
# (`sketch_pieces`), not of the strokes as drawn.
TOKENS_VERSION = 2


@dataclass
class HeadSettings:
    """Training settings of the head (saved in its checkpoint)."""

    epochs: int = 30
    batch_size: int = 32
    lr: float = 1e-3
    final_lr_fraction: float = 0.05
    weight_decay: float = 1e-2
    seed: int = 0
    threads: int = 1
    head: HeadConfig = None
    init: str | None = None  # a head file whose weights start the training (`warm_start`)

    def __post_init__(self):
        if self.head is None:
            self.head = HeadConfig()


@dataclass
class Item:
    """One sample for the head: its tokens and targets."""

    tokens: Tokens
    op: int
    noise: int
    roles: torch.Tensor  # (S,) int64 curve label per stroke
    face: int  # index of the base face among the face tokens, -1 not in view


def _sample_items(model: Sketch2CADNet, a: dict, meta: list[dict], sl: slice) -> list[Item]:
    """The items of the samples `sl` of a shard's arrays `a` (their `meta`): tokens and
    roles of the pieces of curves `interpret` reads (`sketch_pieces`)."""
    cut = [
        sketch_pieces(m["strokes"], a["curve_label"][j], a["stroke_mask"][j])
        for m, j in zip(meta, range(sl.start, sl.stop), strict=True)
    ]
    with torch.inference_mode():
        u = feature_maps(model, torch.from_numpy(decode_inputs(a, sl)))
        toks = batch_tokens(u, [pieces for pieces, _ in cut], a["face_id"][sl])
    return [
        _item(t, roles, a, j)
        for t, (_, roles), j in zip(toks, cut, range(sl.start, sl.stop), strict=True)
    ]


def _item(t: Tokens, roles: list[int], a: dict, j: int) -> Item:
    face_id, label = a["face_id"][j], a["face_label"][j] > 0
    base = (
        np.bincount(face_id[label & (face_id >= 0)].astype(np.int64)).argmax()
        if label.any()
        else -1
    )
    where = (t.face_ids == int(base)).nonzero()
    return Item(
        t,
        int(a["op_type"][j]),
        int(a["noise_level"][j]),
        torch.tensor(roles, dtype=torch.int64),
        int(where[0, 0]) if len(where) else -1,
    )


def extract(
    data: Path,
    model: Sketch2CADNet,
    cache: Path | None = None,
    limit: int | None = None,
    batch: int = 16,
    unet: str = "",
) -> list[Item]:
    """Every sample's tokens and targets. With a `cache` folder, each whole shard's items
    are kept there as they are made, so an interrupted extraction resumes by shard; a
    cached shard is reused only for the same data, count, seed and `unet` (its SHA-256),
    so runs that share a cache (the ablation) read the U-Net once."""
    ds = Dataset(data)
    n = min(len(ds), limit) if limit else len(ds)
    items: list[Item] = []
    with tqdm(total=n, desc="head tokens", unit="sample", leave=False) as bar:
        for k in ds.shards:
            meta = ds.shard_meta(k)
            take = min(len(meta), n - len(items))
            path = cache / f"tokens-{k:05d}.pt" if cache is not None else None
            key = json.dumps(
                {
                    "data": str(Path(data).resolve()),
                    "shard": k,
                    "take": take,
                    "seed": ds.manifest.get("seed"),
                    "unet": unet,
                    "tokens": TOKENS_VERSION,
                },
                sort_keys=True,
            )
            if path is not None and path.exists():
                saved = torch.load(path, weights_only=False)
                if saved["key"] == key:
                    items += saved["items"]
                    bar.update(take)
                    continue
            a, shard_items = ds.shard_arrays(k), []
            for i in range(0, take, batch):
                sl = slice(i, min(i + batch, take))
                got = _sample_items(model, a, meta[sl], sl)
                shard_items += got
                bar.update(len(got))
            if path is not None:
                path.parent.mkdir(parents=True, exist_ok=True)
                with atomic_path(path) as tmp:
                    torch.save({"key": key, "items": shard_items}, tmp)
            items += shard_items
            if len(items) >= n:
                break
    return items


def losses(head: StructureHead, items: list[Item]) -> tuple[torch.Tensor, ...]:
    """(classification, stroke role, base face) losses of a batch, each a per-sample mean."""
    logits, roles, faces = head(*collate([it.tokens for it in items]))
    op = torch.tensor([it.op for it in items])
    cls = F.cross_entropy(logits, op)
    role_terms, face_terms = [], []
    for j, it in enumerate(items):
        if len(it.roles):
            r = roles[j, : len(it.roles), ROLE_OFFSETS[it.op] : ROLE_OFFSETS[it.op] + ROLES[it.op]]
            role_terms.append(F.cross_entropy(r, it.roles))
        if it.face >= 0:
            face_terms.append(F.cross_entropy(faces[j, :, it.op][None], torch.tensor([it.face])))
    zero = logits.sum() * 0
    return (
        cls,
        torch.stack(role_terms).mean() if role_terms else zero,
        torch.stack(face_terms).mean() if face_terms else zero,
    )


def training_items(
    sets: Sequence[Path],
    model: Sketch2CADNet,
    cache: Path,
    limit: int | None = None,
    unet: str = "",
) -> tuple[list[Item], dict]:
    """The items of every data set in `sets`, in that order (each its first `limit`
    samples, default all), each set's tokens cached in its own folder cache/<its name>;
    and how many each gave (path -> count). Raises ValueError for two sets of one name
    (they would share a cache folder)."""
    names = [Path(d).name for d in sets]
    if len(set(names)) < len(names):
        raise ValueError(
            f"training sets need distinct folder names (their token caches): "
            f"{', '.join(map(str, sets))}"
        )
    items, counts = [], {}
    for d in sets:
        got = extract(d, model, cache / Path(d).name, limit=limit, unet=unet)
        counts[str(d)] = len(got)
        items += got
    return items, counts


def train_head(
    data: Path | Sequence[Path],
    out: Path,
    settings: HeadSettings,
    weights: Path | None = None,
    tokens_cache: Path | None = None,
    count: int | None = None,
) -> Path:
    """Train the head on the union of the data sets `data` (one folder or several;
    the first `count` samples of each, default all) with the U-Net of `weights` frozen;
    a rerun with the same `out` resumes after the last finished epoch. Tokens are cached
    per set in `tokens_cache` (default out/tokens; `training_items`). Returns
    out/HEAD_NAME."""
    sets = [Path(data)] if isinstance(data, (str, Path)) else [Path(d) for d in data]
    torch.set_num_threads(settings.threads)
    out.mkdir(parents=True, exist_ok=True)
    unet_path = resolve(weights)
    model, _ = load_model(unet_path)
    unet_sha = sha256_of(unet_path)
    items, counts = training_items(sets, model, tokens_cache or out / "tokens", count, unet_sha)
    settings.head.channels = feature_channels(model)
    head, log = fit(items, out / "head-checkpoint.pt", settings)
    final = out / HEAD_NAME
    save_head(
        final,
        head.eval(),
        settings=asdict(settings),
        log=log,
        train_samples=len(items),
        data=" + ".join(map(str, sets)),
        data_counts=counts,
        unet=str(unet_path),
        unet_sha256=unet_sha,
    )
    return final


def warm_start(head: StructureHead, path: str | Path) -> None:
    """Start `head` from the weights of the head file at `path`, of the same settings
    but perhaps fewer classes (an earlier LABELLED): each of its tensors is copied into
    the leading rows of `head`'s, so its classes and their roles keep what they learnt
    and only the new ones start afresh.

    Raises:
        ValueError: a tensor `head` lacks or that does not fit in its own.
    """
    state = torch.load(path, map_location="cpu", weights_only=False)["model"]
    own = head.state_dict()
    for name, value in state.items():
        mine = own.get(name)
        if (
            mine is None
            or mine.dim() != value.dim()
            or any(a < b for a, b in zip(mine.shape, value.shape, strict=True))
        ):
            raise ValueError(
                f"{path}: its {name} {tuple(value.shape)} does not fit this head's "
                f"{None if mine is None else tuple(mine.shape)} (other settings?)"
            )
        mine[tuple(slice(0, n) for n in value.shape)] = value
    head.load_state_dict(own)


def fit(items: list[Item], ckpt_path: Path, s: HeadSettings) -> tuple[StructureHead, list]:
    """The head trained on `items` (AdamW, warm-up then cosine decay), checkpointed to
    `ckpt_path` after every epoch and resumed from it; returns it and its epoch log. It
    starts from the weights of `s.init` when given (`warm_start`)."""
    torch.manual_seed(s.seed)
    head = StructureHead(s.head)
    if s.init:
        warm_start(head, s.init)
    opt = torch.optim.AdamW(head.parameters(), lr=s.lr, weight_decay=s.weight_decay)
    epoch, log = 0, []
    if ckpt_path.exists():
        head, ckpt = load_head(ckpt_path)
        opt = torch.optim.AdamW(head.parameters(), lr=s.lr, weight_decay=s.weight_decay)
        opt.load_state_dict(ckpt["optimizer"])
        epoch, log = ckpt["epoch"], ckpt["log"]
        print(f"train-head: resuming after epoch {epoch}")
    steps_per_epoch = math.ceil(len(items) / s.batch_size)
    total = s.epochs * steps_per_epoch
    head.train()
    for e in range(epoch, s.epochs):
        t0 = time.perf_counter()
        order = torch.randperm(
            len(items), generator=torch.Generator().manual_seed(s.seed * 1000 + e)
        )
        sums = np.zeros(3)
        for b in range(steps_per_epoch):
            step = e * steps_per_epoch + b
            floor = s.lr * s.final_lr_fraction
            lr = floor + (s.lr - floor) * 0.5 * (1 + math.cos(math.pi * step / total))
            for g in opt.param_groups:
                g["lr"] = lr * min(1.0, (step + 1) / 50)
            batch = [items[int(i)] for i in order[b * s.batch_size : (b + 1) * s.batch_size]]
            terms = losses(head, batch)
            opt.zero_grad(set_to_none=True)
            sum(terms).backward()
            torch.nn.utils.clip_grad_norm_(head.parameters(), 5.0)
            opt.step()
            sums += [t.item() for t in terms]
        row = {
            "epoch": e + 1,
            "cls": sums[0] / steps_per_epoch,
            "role": sums[1] / steps_per_epoch,
            "face": sums[2] / steps_per_epoch,
            "seconds": round(time.perf_counter() - t0, 1),
        }
        log.append(row)
        print(
            f"train-head: epoch {e + 1}/{s.epochs}: cls {row['cls']:.4f} role "
            f"{row['role']:.4f} face {row['face']:.4f} ({row['seconds']} s)",
            flush=True,
        )
        save_head(
            ckpt_path, head, optimizer=opt.state_dict(), epoch=e + 1, log=log, settings=asdict(s)
        )
    return head, log


def evaluate_head(
    data: Path,
    head_path: Path,
    weights: Path | None = None,
    limit: int | None = None,
    batch: int = 16,
) -> dict:
    """The paper's metrics on `data` for the U-Net's own maps ("unet") and for the head's
    choices painted into F and C ("head"), from one pass of the U-Net (`score`)."""
    model, _ = load_model(resolve(weights))
    s = score(data, model, load_head(head_path)[0], limit, batch)
    return {"data": s.data, "unet": s.unet.summary(), "head": s.head.summary()}
