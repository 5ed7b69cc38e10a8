# SPDX-License-Identifier: LGPL-2.1-or-later
"""Pictures of samples for a person to check: the sketch over the shaded context, with
the labels in colour."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from Sketch2CADWorkbench.render.picture import contact_sheet, write_png

from .dataset import Dataset
from .sample import Sample

# Curve labels 0 / 1 / 2: extrude profile / offset, bevel l' / l, start / profile / end.
LABEL_COLOURS = {0: (225, 50, 30), 1: (20, 150, 40), 2: (160, 40, 210)}
FACE_TINT = (70, 140, 255)  # the base face f (F~)
LIGHT = np.array([0.35, 0.5, 0.8]) / np.linalg.norm([0.35, 0.5, 0.8])  # camera space


def overlay(sample: Sample) -> np.ndarray:
    """(H, W, 3) uint8 RGB: the context shaded from its normals (N, camera space), the
    base face tinted blue, and each stroke pixel coloured by its curve label."""
    fg = sample.face_id >= 0  # D is 0 on the farthest foreground pixels too
    n = np.moveaxis(sample.normal, 0, -1) - 1.0
    light = np.clip(n @ LIGHT, 0.0, 1.0)
    shade = np.where(fg, 90 + 150 * light, 255.0)
    img = np.repeat(shade[..., None], 3, axis=2)
    face = sample.face_label > 0
    img[face] = 0.55 * img[face] + 0.45 * np.array(FACE_TINT)
    mask = sample.stroke_mask > 0
    for label, colour in LABEL_COLOURS.items():
        img[mask & (sample.curve_label == label)] = colour
    return img.astype(np.uint8)


def caption(sample: Sample) -> str:
    return (
        f"{sample.op_type.value} len {len(sample.context.operations) + 1} "
        f"noise {sample.noise_level}"
    )


def write_preview(ds: Dataset, path: str | Path, count: int = 24, cols: int = 6) -> None:
    """A contact sheet of the data set's first `count` samples (see `overlay`): base face
    blue, curve labels 0/1/2 red/green/purple, captioned with operator, sequence length
    and noise level."""
    samples = [ds.sample(i) for i in range(min(count, len(ds)))]
    if not samples:
        raise ValueError(f"{ds.folder}: no complete shard to preview")
    write_png(
        contact_sheet([overlay(s) for s in samples], cols, [caption(s) for s in samples]), path
    )
