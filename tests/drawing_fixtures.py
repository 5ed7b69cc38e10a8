# SPDX-License-Identifier: LGPL-2.1-or-later
"""Synthetic drawings for the decoding tests (tests/inference)."""

import numpy as np

from Sketch2CADWorkbench.sketch.labels import END, PROFILE, START

SIZE = 256


def prism_drawing(
    n: int, seed: int = 0, noise: float = 3.6, shift=(10.0, -70.0)
) -> tuple[list[np.ndarray], list[int]]:
    """An orthographic drawing of a prism over an irregular n-gon (no two corners close): its
    start outline, the end outline (the start moved by `shift`, pixels) and the profiles,
    each stroke's ends moved by `noise` px per axis (level 1: 3.6), in a random order."""
    rng = np.random.default_rng(seed)
    angle = 2 * np.pi * (np.arange(n) + rng.uniform(-0.25, 0.25, n)) / n
    base = np.array([128.0, 150.0]) + 50 * np.stack([np.cos(angle), 0.6 * np.sin(angle)], 1)
    far = base + np.asarray(shift)
    lines = [(base[i], base[(i + 1) % n], START) for i in range(n)]
    lines += [(far[i], far[(i + 1) % n], END) for i in range(n)]
    lines += [(base[i], far[i], PROFILE) for i in range(n)]
    strokes, labels = [], []
    for k in rng.permutation(len(lines)):
        a, b, label = lines[k]
        a, b = a + rng.normal(0, noise, 2), b + rng.normal(0, noise, 2)
        strokes.append(np.linspace(a, b, 12))
        labels.append(label)
    return strokes, labels
