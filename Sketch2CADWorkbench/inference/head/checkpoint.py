# SPDX-License-Identifier: LGPL-2.1-or-later
"""A head's checkpoint: its weights and config, and which U-Net it reads."""

from __future__ import annotations

import hashlib
from dataclasses import asdict, fields
from pathlib import Path

import torch

from ...brep.files import atomic_path
from .model import HeadConfig, StructureHead

HEAD_FORMAT = "sketch2cad-head"


def save_head(path: str | Path, head: StructureHead, **extra) -> None:
    """The head's weights and config (plus `extra`), written atomically."""
    with atomic_path(path) as tmp:
        torch.save(
            {
                "format": HEAD_FORMAT,
                "config": asdict(head.config),
                "model": head.state_dict(),
                **extra,
            },
            tmp,
        )


def load_head(path: str | Path) -> tuple[StructureHead, dict]:
    """A head (eval mode) and its checkpoint dictionary. Raises ValueError for a file
    that is not a head checkpoint. A pickle: load only the project's own files."""
    try:
        ckpt = torch.load(path, map_location="cpu", weights_only=False)
    except FileNotFoundError:
        raise
    except Exception as e:
        raise ValueError(
            f"{path}: not a readable {HEAD_FORMAT} checkpoint ({type(e).__name__}: {str(e)[:120]})"
        ) from None
    if not isinstance(ckpt, dict) or ckpt.get("format") != HEAD_FORMAT:
        raise ValueError(f"{path}: not a {HEAD_FORMAT} checkpoint")
    known = {f.name for f in fields(HeadConfig)}
    config = {k: v for k, v in ckpt["config"].items() if k in known}
    if "classes" not in config and "cls_out.weight" in ckpt.get("model", {}):
        # a head saved before the setting: as many classes as its class layer has
        config["classes"] = int(ckpt["model"]["cls_out.weight"].shape[0])
    head = StructureHead(HeadConfig(**config))
    try:
        head.load_state_dict(ckpt["model"])
    except RuntimeError as e:  # another layout: fewer classes, or another version's head
        raise ValueError(
            f"{path}: a head of another layout than this version's "
            f"({str(e).splitlines()[-1].strip()[:160]}); train one with sketch2cad train-head"
        ) from None
    return head.eval(), ckpt


def sha256_of(path: str | Path) -> str:
    """The hex SHA-256 of a file (which U-Net a head was trained on)."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()
