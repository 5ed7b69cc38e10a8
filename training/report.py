# SPDX-License-Identifier: LGPL-2.1-or-later
"""Pictures of training and evaluation: the loss curves of a run, and the evaluation
report (confusion matrix, per-operator bars against the paper, example predictions)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import torch

from .metrics import NAMES, PAPER_TABLE_1, curve_classes, face_iou


def plot_curves(log_path: Path, png: Path, face_dice: float = 0.0) -> None:
    """Training losses per logged step and validation metrics per epoch, as a PNG
    (face_dice: the Dice term's weight, named in the face loss's title when used)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = [json.loads(line) for line in log_path.read_text().splitlines() if line.strip()]
    tr = [r for r in rows if r["kind"] == "train"]
    va = [r for r in rows if r["kind"] == "val"]
    fig, axes = plt.subplots(1, 4, figsize=(17, 3.8))
    for ax, key, title in zip(
        axes,
        ("cls", "face", "curve"),
        (
            "classification (weighted CE)",
            "base face F (MSE + Dice)" if face_dice else "base face F (MSE)",
            "curve C on strokes (MSE)",
        ),
        strict=False,
    ):
        ax.plot([r["step"] for r in tr], [r[key] for r in tr], lw=0.8, label="train")
        if va:
            ax.plot([r["step"] for r in va], [r[key] for r in va], "o-", label="validation")
        ax.set(title=title, xlabel="step", yscale="log")
        ax.grid(alpha=0.3)
        ax.legend()
    ax = axes[3]
    if va:
        steps = [r["step"] for r in va]
        ax.plot(steps, [r["classification_accuracy"] for r in va], "k.-", label="class. acc.")
        for name in ("extrude", "bevel", "addsub", "sweep"):
            ax.plot(
                steps,
                [r["per_operator"][name]["face_iou"] or 0 for r in va],
                ".-",
                label=f"{name} face IoU",
            )
            ax.plot(
                steps,
                [r["per_operator"][name]["curve_accuracy"] or 0 for r in va],
                ".:",
                label=f"{name} curve acc.",
            )
        ax.legend(fontsize=6, ncol=2, loc="lower right")
    ax.set(title="validation metrics", xlabel="step", ylim=(0, 1))
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(png, dpi=80)
    plt.close(fig)


def report(result: dict, examples: list[dict], path: Path) -> None:
    """Confusion matrix, per-operator bars against the paper, and example predictions."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap

    rows = 1 + len(examples)
    fig = plt.figure(figsize=(15, 3.6 + 2.1 * len(examples)))
    grid = fig.add_gridspec(rows, 5, height_ratios=[1.7] + [1] * len(examples))
    ax = fig.add_subplot(grid[0, :2])
    # the U-Net's classes, the paper's four: it is scored on their samples alone
    names = [n for n in NAMES if n in PAPER_TABLE_1["face_iou"]]
    k = len(names)
    cm = np.array(result["confusion_matrix"]["rows_true_cols_predicted"])[:k, :k]
    ax.imshow(cm / np.maximum(cm.sum(1, keepdims=True), 1), cmap="Blues", vmin=0, vmax=1)
    for i in range(k):
        for j in range(k):
            ax.text(j, i, str(cm[i, j]), ha="center", va="center")
    ax.set_xticks(range(k), names)
    ax.set_yticks(range(k), names)
    ax.set(
        xlabel="predicted",
        ylabel="true",
        title=f"classification accuracy {result['classification_accuracy']:.4f} "
        f"(n = {result['n']})",
    )
    ax = fig.add_subplot(grid[0, 2:])
    x = np.arange(k)
    per = result["per_operator"]
    for dx, values, label, alpha in (
        (-0.3, [per[n]["face_iou"] or 0 for n in names], "face IoU", 1.0),
        (-0.1, [PAPER_TABLE_1["face_iou"][n] for n in names], "face IoU, paper", 0.4),
        (0.1, [per[n]["curve_accuracy"] or 0 for n in names], "curve accuracy", 1.0),
        (0.3, [PAPER_TABLE_1["curve_accuracy"][n] for n in names], "curve accuracy, paper", 0.4),
    ):
        bars = ax.bar(x + dx, values, 0.2, label=label, alpha=alpha)
        ax.bar_label(bars, fmt="%.3f", fontsize=6)
    ax.set_xticks(x, [f"{n} (n={per[n]['n']})" for n in names])
    ax.set(
        ylim=(0, 1.08),
        title=f"per operator; networks {result['latency_ms']['networks_median']:.1f}"
        " ms per sketch (median, batch 1, 2 threads)",
    )
    ax.legend(fontsize=7, loc="lower left")
    curves = ListedColormap(["#1f77b4", "#d62728", "#2ca02c"])
    for r, e in enumerate(examples, start=1):
        panels = [
            (
                "sketch over D",
                np.dstack(
                    [np.maximum(e["depth"], e["sketch"])] * 2 + [e["depth"] * (1 - e["sketch"])]
                ),
                {},
            ),
            ("F (ours)", e["face"], {"cmap": "gray", "vmin": 0, "vmax": 1}),
            ("F~", e["face_label"], {"cmap": "gray", "vmin": 0, "vmax": 1}),
            (
                "C class on strokes (ours)",
                np.ma.masked_where(
                    e["mask"] < 0.5,
                    curve_classes(torch.from_numpy(e["curve"])[None], torch.tensor([e["op"]]))[
                        0
                    ].numpy(),
                ),
                {"cmap": curves, "vmin": 0, "vmax": 2, "interpolation": "nearest"},
            ),
            (
                "C~",
                np.ma.masked_where(e["mask"] < 0.5, e["curve_label"]),
                {"cmap": curves, "vmin": 0, "vmax": 2, "interpolation": "nearest"},
            ),
        ]
        for col, (title, img, kw) in enumerate(panels):
            ax = fig.add_subplot(grid[r, col])
            ax.imshow(img, **kw)
            ax.set_xticks([])
            ax.set_yticks([])
            if col == 0:
                title = f"{NAMES[e['op']]} (read as {NAMES[e['pred']]})"
            elif col == 1:
                iou = face_iou(
                    torch.from_numpy(e["face"])[None], torch.from_numpy(e["face_label"])[None]
                )[0]
                title += f", IoU {float(iou):.3f}"
            ax.set_title(title, fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)
