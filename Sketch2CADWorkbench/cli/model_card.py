# SPDX-License-Identifier: LGPL-2.1-or-later
"""Ship a training run: copy its weights into the package with a model card and thresholds.

`sketch2cad model-card --run runs/main --eval 1=runs/eval-l1.json 2=... 3=...`: the card
states the data, the training time and hardware, and the table measured by
`sketch2cad eval` at each noise level; thresholds.json (level-1 figures less a margin
for the 96-sample set of tests/inference/test_shipped_weights.py) guards against
regressions. Run by `make weights`, which also makes the data and trains.
"""

from __future__ import annotations

import argparse
import json
import platform
import shutil
import sys
from pathlib import Path

import torch

from training.metrics import PAPER_TABLE_1
from training.report import plot_curves

from ..inference.weights import HEAD_NAME

ROOT = Path(__file__).resolve().parents[2]
WEIGHTS = ROOT / "Sketch2CADWorkbench" / "inference" / "weights"
OPS = ("extrude", "bevel", "addsub", "sweep")
# Margins under the level-1 figures for the regression test's small set (96 samples,
# about 12 per operator for the rarest): wide enough for its sampling spread, narrow
# enough that a broken network fails.
MARGIN_CLASSIFICATION, MARGIN_SEGMENTATION = 0.06, 0.15


def pct(x) -> str:
    return "n/a" if x is None else f"{100 * x:.1f}"


def recovery_count(evals: dict[str, dict]) -> int:
    """Samples the recovery rates were measured on (per level; the first level's)."""
    first = evals[min(evals)]["per_operator"]
    return sum(d.get("recovery_n") or 0 for d in first.values())


def table(evals: dict[str, dict]) -> list[str]:
    rows = [
        "| noise level | n | classification | "
        + " | ".join(
            f"{op}: face IoU / curve acc. / recovery [with flip] / fitting alone" for op in OPS
        )
        + " | networks ms |",
        "|---|---|---|" + "---|" * len(OPS) + "---|",
    ]
    for level, r in sorted(evals.items()):
        cells = []
        for op in OPS:
            d = r["per_operator"][op]
            cells.append(
                f"{pct(d['face_iou'])} / {pct(d['curve_accuracy'])} / "
                f"{pct(d.get('recovery_rate'))} [{pct(d.get('recovery_rate_with_flip'))}] / "
                f"{pct(d.get('fitting_recovery_rate'))}"
            )
        rows.append(
            f"| {level} | {r['n']} | {pct(r['classification_accuracy'])} | "
            + " | ".join(cells)
            + f" | {r['latency_ms']['networks_median']:.1f} |"
        )
    rows.append(
        f"| paper, level 1 | | {pct(PAPER_TABLE_1['classification_accuracy'])} | "
        + " | ".join(
            f"{pct(PAPER_TABLE_1['face_iou'][op])} / "
            f"{pct(PAPER_TABLE_1['curve_accuracy'][op])} / - / -"
            for op in OPS
        )
        + " | (GPU) |"
    )
    return rows


def ablation(runs: list[tuple[dict, dict | None]]) -> list[str]:
    """The structured heads' ablation table from `sketch2cad train-head --json` outputs
    (with each run's head checkpoint, or None): per held-out set, the U-Net's own maps
    (once) and each head's choices painted into F and C, scored on the same samples with
    the paper's metrics."""
    out = [
        "| data | n | reading | classification | "
        + " | ".join(f"{op}: face IoU / curve acc." for op in OPS)
        + " |",
        "|---|---|---|---|" + "---|" * len(OPS),
    ]
    rows = []
    for k, (scores, head) in enumerate(runs):
        label = (
            f"head, {head['config']['layers']} attention layers"
            + (f", width {head['config']['width']}" if "width" in head["config"] else "")
            if head
            else "head"
        )
        for data, result in scores.items():
            for name in ("unet", "head") if k == 0 else ("head",):
                if name in result:
                    rows.append((data, label if name == "head" else name, result[name]))
    for data, name, r in sorted(rows, key=lambda row: row[0]):
        cells = [
            f"{pct(r['per_operator'][op]['face_iou'])} / "
            f"{pct(r['per_operator'][op]['curve_accuracy'])}"
            for op in OPS
        ]
        out.append(
            f"| {Path(data).name} | {r['n']} | {name} | "
            f"{pct(r['classification_accuracy'])} | " + " | ".join(cells) + " |"
        )
    out.append(
        f"| paper, Table 1 | | | {pct(PAPER_TABLE_1['classification_accuracy'])} | "
        + " | ".join(
            f"{pct(PAPER_TABLE_1['face_iou'][op])} / {pct(PAPER_TABLE_1['curve_accuracy'][op])}"
            for op in OPS
        )
        + " |"
    )
    return out


HEADS_HEADING = "## Structured heads (ablation; not shipped)"
GUARD_HEADING = "## Regression guard"
SHIPPED_HEAD_HEADING = f"## Structured head (shipped: {HEAD_NAME})"
HEAD_COMMANDS = [
    "sketch2cad datagen --out data/head-train --count 27648 --seed 1 --noise-level mix",
    "sketch2cad datagen --curved --out data/curved-train --count 1536 --seed 2 --noise-level mix",
    "sketch2cad datagen --curved --out data/curved-50003 --count 100 --seed 50003 --noise-level 1",
    "sketch2cad datagen --out data/head-test-lN --count 400 --seed 4000N --noise-level N",
    "sketch2cad train-head --data data/head-train data/curved-train --out runs/head --epochs 20 "
    "--width 128 --tokens runs/head-tokens --weights runs/main --eval data/head-test-l1 "
    "data/head-test-l3 data/curved-50003 --json runs/head/scores.json",
    "sketch2cad train-head --data data/head-train data/curved-train --out runs/head-noctx "
    "--epochs 20 --width 128 --layers 0 --tokens runs/head-tokens --weights runs/main "
    "--eval data/head-test-l1 data/head-test-l3 data/curved-50003 "
    "--json runs/head-noctx/scores.json",
    "sketch2cad datagen --out data/heldout-lN --count 200 --seed 3000N --noise-level N",
    "python scripts/recovery_with_head.py --data data/heldout-lN --head runs/head "
    "--weights runs/main --limit 200 --json runs/head-recovery/heldout-lN.json",
]


def heads_section(
    runs: list[tuple[dict, dict | None]],
    recovery: dict[str, dict] | None = None,
    shipped: bool = False,
) -> list[str]:
    """The model card's section on the structured heads (inference/head/): `runs`,
    each run's `train-head --json` scores and head checkpoint dictionary (or None), the
    first being the head that ships when `shipped`; `recovery`, per data set the
    end-to-end rows of scripts/recovery_with_head.py --json."""
    trained = []
    for _, head in runs:
        if head:
            params = sum(v.numel() for v in head["model"].values())
            s = head["settings"]
            trained += [
                f"- Head, {head['config']['layers']} attention layers, width "
                f"{head['config'].get('width')}: {params} "
                f"parameters ({json.dumps(head['config'])}); {s['epochs']} epochs "
                f"of {head.get('train_samples')} samples of {_trained_on(head)} in "
                f"{sum(r['seconds'] for r in head['log']) / 60:.1f} min on "
                f"{s['threads']} torch thread(s), on the features of the U-Net with "
                f"SHA-256 {str(head.get('unet_sha256'))[:12]}..."
            ]
    return [
        SHIPPED_HEAD_HEADING if shipped else HEADS_HEADING,
        "The heads read the frozen U-Net's features per stroke (sampled along the polyline, "
        "with its geometry) and per visible face (pooled over the face-ID map), with a "
        "small transformer for the context between them (its attention biased by how near "
        "two strokes' ends lie and by how much of a stroke lies on a face), and choose each "
        "stroke's role (with the counts the operator's drawing has: a prism's n start, n "
        "profile and n end strokes, a sweep's 1, 2, 1, a bevel's one l) and the base face; "
        "the choices are painted back into C and F, so the paper's curve "
        "accuracy and face IoU score them unchanged. Rows: `unet`, this network's own maps; "
        "`head`, the head's choices; each segmentation on the ground-truth operator's maps, "
        "as the paper scores them. Printed by `sketch2cad train-head ... --eval DIR ...` "
        "(`make weights`); figures in %."
        + (
            f" The predictor loads `{HEAD_NAME}` with the U-Net beside it and refuses it "
            "for any U-Net but the one whose SHA-256 it records."
            if shipped
            else ""
        ),
        "",
        *trained,
        "",
        *ablation(runs),
        "",
        *(end_to_end(recovery) if recovery else []),
        "How to reproduce (`make weights`):",
        "```",
        *HEAD_COMMANDS,
        "```",
        "",
    ]


def _trained_on(head: dict) -> str:
    """The head's training data: each set with its count when it trained on several."""
    counts = head.get("data_counts") or {}
    if len(counts) > 1:
        return "the union of " + ", ".join(f"{n} of `{d}`" for d, n in counts.items())
    return f"`{head.get('data')}`"


def end_to_end(recovery: dict[str, dict]) -> list[str]:
    """Recovery of whole interpret steps with the U-Net alone and with the head, per
    data set (scripts/recovery_with_head.py --json), strict [with the flip]."""
    out = [
        "End to end (interpret, regularization off; recovered: volume IoU >= 0.95 with "
        "the truth; in brackets with the named one-click flip of the Boolean), %; "
        "interpret ms is wall time on the shared project machine, comparable only between "
        "rows run at the same load:",
        "",
        "| data | reading | "
        + " | ".join(f"{op} (n)" for op in OPS)
        + " | interpret ms (median) |",
        "|---|---|" + "---|" * len(OPS) + "---|",
    ]
    for data, rows in recovery.items():
        for name, r in rows.items():
            per = r["per_operator"]
            out.append(
                f"| {data} | {name} | "
                + " | ".join(
                    f"{pct(per[op]['recovery_rate'])} [{pct(per[op]['recovery_rate_with_flip'])}]"
                    f" ({per[op]['recovery_n']})"
                    for op in OPS
                )
                + f" | {r['interpret_median_ms']:.0f} |"
            )
    return out + [""]


def _head_beside(scores: Path) -> dict | None:
    """The head checkpoint in the scores' run folder, if there is one."""
    path = scores.parent / HEAD_NAME
    return torch.load(path, map_location="cpu", weights_only=False) if path.exists() else None


def plot_recovery(evals: dict[str, dict], path: Path) -> None:
    """Bars per operator and noise level: end-to-end recovery, the same with the one-click
    flip of the Boolean, and the fitting stage alone; the 90% target as a line."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    levels = sorted(evals)
    kinds = (
        ("recovery_rate", "end to end", 1.0),
        ("recovery_rate_with_flip", "end to end, with the named flip", 0.55),
        ("fitting_recovery_rate", "fitting alone (ground-truth maps)", 0.3),
    )
    fig, axes = plt.subplots(1, len(levels), figsize=(4.2 * len(levels), 3.6), sharey=True)
    for ax, level in zip(np.atleast_1d(axes), levels):
        per = evals[level]["per_operator"]
        x = np.arange(len(OPS))
        for k, (key, label, alpha) in enumerate(kinds):
            bars = ax.bar(
                x + (k - 1) * 0.27,
                [per[op].get(key) or 0 for op in OPS],
                0.27,
                label=label,
                alpha=alpha,
                color="#1f77b4",
            )
            ax.bar_label(bars, fmt="%.2f", fontsize=6)
        ax.axhline(0.9, color="#d62728", lw=1, ls="--", label="target 0.90")
        ax.set_xticks(x, [f"{op}\n(n={per[op].get('recovery_n', 0)})" for op in OPS], fontsize=8)
        ax.set(ylim=(0, 1.08), title=f"noise level {level}")
    first = np.atleast_1d(axes)[0]
    first.set_ylabel("recovered (volume IoU >= 0.95)")
    fig.legend(*first.get_legend_handles_labels(), loc="upper center", ncol=4, fontsize=8)
    fig.tight_layout(rect=(0, 0, 1, 0.9))
    fig.savefig(path, dpi=90)
    plt.close(fig)


def targets_met(level1: dict) -> str:
    """Which of the paper's level-1 figures these weights reach, in words."""
    met, missed = [], []
    (
        met
        if level1["classification_accuracy"] >= PAPER_TABLE_1["classification_accuracy"]
        else missed
    ).append("classification")
    for metric, name in (("face_iou", "face IoU"), ("curve_accuracy", "curve accuracy")):
        for op in OPS:
            ours = level1["per_operator"][op][metric]
            (met if ours >= PAPER_TABLE_1[metric][op] else missed).append(f"{op} {name}")
    return (
        f"these are met: {', '.join(met) or 'none'}; these are not: {', '.join(missed) or 'none'}"
    )


def add_arguments(ap: argparse.ArgumentParser) -> None:
    ap.add_argument(
        "--run",
        type=Path,
        help="training run folder (with --eval; without "
        "both, only the card's heads section is rewritten)",
    )
    ap.add_argument(
        "--eval",
        nargs="+",
        metavar="LEVEL=JSON",
        help="`sketch2cad eval` results per noise level of the held-out sets",
    )
    ap.add_argument(
        "--heads",
        type=Path,
        nargs="+",
        metavar="JSON",
        help="`sketch2cad train-head --json` scores, one per head (the head "
        "checkpoint beside each): the heads' ablation section",
    )
    ap.add_argument(
        "--head-recovery",
        type=Path,
        nargs="+",
        metavar="JSON",
        help="scripts/recovery_with_head.py --json results: the heads' end-to-end table",
    )
    ap.add_argument(
        "--ship-head",
        action="store_true",
        help=f"copy the first --heads run's {HEAD_NAME} beside the shipped "
        "U-Net (it must have been trained on that U-Net's features)",
    )


def _heads(args: argparse.Namespace) -> list[str]:
    """The heads section from the arguments; with --ship-head, the head copied into the
    package first. Raises ValueError for a head of another U-Net."""
    if not args.heads:
        return []
    if args.ship_head:
        from ..inference.head.checkpoint import sha256_of

        head = _head_beside(args.heads[0])
        if head is None or head.get("unet_sha256") != sha256_of(WEIGHTS / "sketch2cad_net.pt"):
            raise ValueError(
                f"{args.heads[0].parent / HEAD_NAME}: not a head trained on "
                f"the features of {WEIGHTS / 'sketch2cad_net.pt'}"
            )
        shutil.copyfile(args.heads[0].parent / HEAD_NAME, WEIGHTS / HEAD_NAME)
    recovery = {p.stem: json.loads(p.read_text()) for p in args.head_recovery or []}
    return heads_section(
        [(json.loads(p.read_text()), _head_beside(p)) for p in args.heads],
        recovery,
        shipped=(WEIGHTS / HEAD_NAME).exists(),
    )


def replace_heads_section(card: str, section: list[str]) -> str:
    """The card with its heads section (from either heading up to the next "## ")
    replaced by `section`, or `section` put before the regression guard."""
    lines = card.splitlines()
    starts = [i for i, ln in enumerate(lines) if ln in (HEADS_HEADING, SHIPPED_HEAD_HEADING)]
    if starts:
        end = next(
            (i for i in range(starts[0] + 1, len(lines)) if lines[i].startswith("## ")), len(lines)
        )
    else:
        starts = [end] = [next(i for i, ln in enumerate(lines) if ln == GUARD_HEADING)]
    return "\n".join(lines[: starts[0]] + section + lines[end:]) + "\n"


def run(args: argparse.Namespace) -> int:
    if (args.run is None) != (args.eval is None) or (args.run is None and not args.heads):
        print(
            "sketch2cad model-card: error: give --run with --eval (the whole card), or "
            "--heads alone (its heads section)",
            file=sys.stderr,
        )
        return 2
    if args.run is None:
        return _write(args, WEIGHTS / "MODEL_CARD.md", None)
    evals = {}
    for item in args.eval:
        level, _, path = item.partition("=")
        evals[level] = json.loads(Path(path).read_text())
    if "1" not in evals:
        print(
            "sketch2cad model-card: error: the level-1 evaluation sets the thresholds: pass 1=JSON",
            file=sys.stderr,
        )
        return 2
    ckpt = torch.load(args.run / "sketch2cad_net.pt", map_location="cpu", weights_only=False)
    WEIGHTS.mkdir(exist_ok=True)
    shutil.copyfile(args.run / "sketch2cad_net.pt", WEIGHTS / "sketch2cad_net.pt")
    _drop_stale_head()
    return _write(args, WEIGHTS / "MODEL_CARD.md", (ckpt, evals))


def _drop_stale_head() -> None:
    """Remove a shipped head that another U-Net's features trained: the predictor would
    refuse it (the new U-Net's card says whether a head for it ships)."""
    from ..inference.head.checkpoint import sha256_of

    path = WEIGHTS / HEAD_NAME
    if path.exists() and torch.load(path, map_location="cpu", weights_only=False).get(
        "unet_sha256"
    ) != sha256_of(WEIGHTS / "sketch2cad_net.pt"):
        path.unlink()
        print(f"removed {path}: trained on another U-Net's features")


def _write(args: argparse.Namespace, card: Path, full: tuple[dict, dict] | None) -> int:
    """The card written: whole (`full`: the U-Net's checkpoint and evaluations) or only
    its heads section; the head shipped first with --ship-head."""
    try:
        heads = _heads(args)
    except (FileNotFoundError, ValueError) as e:
        print(f"sketch2cad model-card: error: {e}", file=sys.stderr)
        return 2
    if full is None:
        card.write_text(replace_heads_section(card.read_text(), heads))
        print(
            f"wrote the heads section of {card}"
            + (f" and {WEIGHTS / HEAD_NAME}" if args.ship_head else "")
        )
        return 0
    ckpt, evals = full
    one = evals["1"]
    limits = {
        "classification_accuracy": round(one["classification_accuracy"] - MARGIN_CLASSIFICATION, 3),
        "per_operator": {
            op: {
                k: round(max(0.0, one["per_operator"][op][k] - MARGIN_SEGMENTATION), 3)
                for k in ("face_iou", "curve_accuracy")
            }
            for op in OPS
        },
    }
    (WEIGHTS / "thresholds.json").write_text(json.dumps(limits, indent=1) + "\n")

    key, s = ckpt["data_key"], ckpt["settings"]
    size_mb = (WEIGHTS / "sketch2cad_net.pt").stat().st_size / 2**20
    lines = [
        "# Model card: sketch2cad_net.pt",
        "",
        "One network (`inference/models.py`): a shared-encoder U-Net over the sketch S, "
        "depth D and normals N (5 channels), pooled from 256x256 to an internal "
        f"{ckpt['config']['internal_size']}x{ckpt['config']['internal_size']}, with the "
        "operator classifier on the bottleneck and per-operator F and C heads. "
        f"Widths {tuple(ckpt['config']['widths'])}; {size_mb:.1f} MB.",
        "Loss: the paper's (Eq. 1, class-weighted cross entropy; Eq. 2, F over the image "
        "and C on stroke pixels)"
        + (
            f", plus a soft Dice term on F of weight {s['face_dice']}, so that small base "
            "faces count as much as large ones."
            if s.get("face_dice")
            else "."
        ),
        "",
        "## Training",
        f"- Data: `sketch2cad datagen` v{key['version']}, {key['count']} samples, seed "
        f"{key['seed']}, noise `{key['noise']}` (levels 1, 2, 3 take turns).",
        f"- {ckpt['trained_steps']} steps of {s['batch_size']} samples "
        f"({ckpt['trained_epochs']:.2f} epochs) in {ckpt['trained_minutes']:.0f} min of "
        f"optimisation, {s['threads']} torch threads on `{s['device']}` ({platform.machine()}; "
        "the project machine: 2 cores, no GPU).",
        f"- Settings: {json.dumps({k: v for k, v in s.items() if k != 'model'})}",
        "- Loss curves: `docs/loss_curves.png`.",
        "",
        "## Measured on held-out sets (seeds 10001, 10002, 10003; 400 samples each)",
        "Face IoU, curve accuracy (paper's definitions), end-to-end recovery rate "
        "(interpreted operation within volume IoU 0.95 of the truth, regularization off; "
        f"first {recovery_count(evals)} samples; in brackets, counting as recovered a step "
        "the other Boolean recovers when the pipeline named it: a boss and a hole that draw "
        "the same lines, paper Fig. 5b) and the same for the fitting stage alone "
        "given the ground-truth operator, F and C, in %; networks' median latency on 2 CPU "
        "threads.",
        "",
        *table(evals),
        "",
        "Recovery per operator and noise level, as bars: `docs/recovery.png`.",
        "",
        "Median interpret step (render + networks + fitting + B-rep), ms: "
        + ", ".join(
            f"level {lvl}: {r['latency_ms'].get('interpret_median', float('nan')):.0f}"
            for lvl, r in sorted(evals.items())
        )
        + ".",
        "",
        "Against the paper: classification at noise level 3 is "
        f"{pct(evals[max(evals)]['classification_accuracy'])}% (the paper's classifier: 53.2%); "
        f"of the level-1 targets {targets_met(evals[min(evals)])}. "
        "The paper's networks trained for 160k-630k iterations on 4 GPUs, these "
        "within the 2-hour budget of a 2-core CPU. The fitting stage "
        "reads stroke roles from geometry when the curve map's do not fit "
        "(`fitting/stroke_roles.py`), which recovers many sketches the networks mislabel.",
        "",
        "## How to reproduce",
        "`make weights` (data, training, evaluation, this card), that is:",
        "```",
        "sketch2cad datagen --out data/train2 --count 20000 --seed 1 --noise-level mix",
        "sketch2cad datagen --out data/test-lN --count 400 --seed 1000N --noise-level N",
        f"sketch2cad train --data data/train2 --out runs/main --minutes {s['minutes']:g} "
        f"--threads {s['threads']}",
        "sketch2cad eval --data data/test-lN --weights runs/main --json runs/eval-lN.json "
        "--report docs/eval-lN.png --recovery 400 --fitting-recovery",
        "(the structured heads: their section's commands)",
        "sketch2cad model-card --run runs/main --eval 1=runs/eval-l1.json ... --heads "
        "runs/head/scores.json runs/head-noctx/scores.json --head-recovery "
        "runs/head-recovery/heldout-l1.json runs/head-recovery/heldout-l3.json [--ship-head]",
        "```",
        "",
        *heads,
        GUARD_HEADING,
        "`thresholds.json`: the level-1 figures less "
        f"{MARGIN_CLASSIFICATION} (classification) and {MARGIN_SEGMENTATION} (face IoU, "
        "curve accuracy); `tests/inference/test_shipped_weights.py` evaluates these weights "
        "on 96 freshly generated samples (seed 9090) against them.",
    ]
    (WEIGHTS / "MODEL_CARD.md").write_text("\n".join(lines) + "\n")
    plot_curves(args.run / "log.jsonl", ROOT / "docs" / "loss_curves.png", s.get("face_dice", 0.0))
    plot_recovery(evals, ROOT / "docs" / "recovery.png")
    print(
        f"wrote {WEIGHTS / 'sketch2cad_net.pt'} ({size_mb:.1f} MB), thresholds.json, "
        "MODEL_CARD.md, docs/loss_curves.png, docs/recovery.png"
    )
    return 0
