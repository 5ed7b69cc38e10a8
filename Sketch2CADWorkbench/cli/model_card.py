# SPDX-License-Identifier: LGPL-2.1-or-later
"""Write the shipped weights' model card, whole, from the evaluations stored in docs/eval/.

`sketch2cad model-card` rewrites inference/weights/MODEL_CARD.md from the shipped files
(their hashes, the U-Net's and the head's checkpoints) and the stored figures: each JSON
file of docs/eval/ holds what a command printed, with the command. The card says what
ships, what it is for and what the strokes cannot tell, the data and compute, the shipped
pipeline's current figures and how to reproduce them; a test checks that the committed
card is what this command writes.

Shipping new weights (`make weights`) stores their evaluations first:
`--run runs/main --eval 1=runs/eval-l1.json 2=... 3=...` copies the run's U-Net into the
package, writes thresholds.json (level-1 figures less a margin for the 96-sample set of
tests/inference/test_shipped_weights.py) and stores the U-Net's figures
(docs/eval/unet.json); `--heads SCORES.json ... [--head-recovery J ...] [--ship-head]`
stores the structured heads' figures (docs/eval/heads.json) and with --ship-head copies
the first head beside the U-Net. The other files (the pipeline's figures per held-out set,
the bounds, the sessions, speed) are updated by running the commands they name.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
from pathlib import Path

import torch

from training.metrics import PAPER_TABLE_1
from training.report import plot_curves

from ..inference.head.checkpoint import sha256_of
from ..inference.weights import HEAD_NAME, WEIGHTS_NAME

ROOT = Path(__file__).resolve().parents[2]
WEIGHTS = ROOT / "Sketch2CADWorkbench" / "inference" / "weights"
EVAL = ROOT / "docs" / "eval"
OPS = ("extrude", "bevel", "addsub", "sweep")  # the U-Net's classes, the paper's four
# the structured head's classes (sketch.labels.LABELLED): the shell too
HEAD_OPS = (*OPS, "shell")
# Margins under the level-1 figures for the regression test's small set (96 samples,
# about 12 per operator for the rarest): wide enough for its sampling spread, narrow
# enough that a broken network fails.
MARGIN_CLASSIFICATION, MARGIN_SEGMENTATION = 0.06, 0.15
# A session "holds" its protocol when a reading can end it at this volume IoU or above.
SESSION_TARGET = 0.97
# The commands of `make weights`, in order (N: each noise level).
UNET_COMMANDS = [
    "sketch2cad datagen --out data/train2 --count 20000 --seed 1 --noise-level mix",
    "sketch2cad datagen --out data/test-lN --count 400 --seed 1000N --noise-level N",
    "sketch2cad train --data data/train2 --out runs/main --minutes 90 --threads 2",
    "sketch2cad eval --data data/test-lN --weights runs/main --json runs/eval-lN.json "
    "--report docs/eval-lN.png --recovery 400 --fitting-recovery",
]
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
    "sketch2cad head-recovery --data data/heldout-lN --head runs/head "
    "--weights runs/main --limit 200 --json runs/head-recovery/heldout-lN.json",
    "sketch2cad model-card --run runs/main --eval 1=runs/eval-l1.json 2=runs/eval-l2.json "
    "3=runs/eval-l3.json --heads runs/head/scores.json runs/head-noctx/scores.json "
    "--head-recovery runs/head-recovery/heldout-l1.json runs/head-recovery/heldout-l3.json "
    "--ship-head",
]
# The shipped head: the head above fine-tuned on sets with shells and rounds, drawn by
# the generator's hand and by people's (`sketch2cad train-head --init`).
TUNED_COMMANDS = [
    "sketch2cad datagen --out data/head-train-8k --count 8192 --seed 1 --noise-level mix",
    "sketch2cad datagen --out data/head-train5 --count 2048 --seed 1 --noise-level mix "
    "--shells --round-share 0.25",
    "sketch2cad datagen --out data/people-train --count 4096 --seed 3 --noise-level mix "
    "--round-share 0.25 --hand people",
    "sketch2cad datagen --curved --out data/curved-train5 --count 512 --seed 2 --noise-level mix",
    "sketch2cad datagen --out data/heldout5-lN --count 300 --seed 3110N --noise-level N "
    "--shells --round-share 0.25",
    "sketch2cad datagen --out data/people-lN --count 200 --seed 3120N --noise-level N "
    "--hand people",
    "sketch2cad train-head --data data/head-train-8k data/head-train5 data/people-train "
    "data/curved-train5 --out runs/head5 --init runs/head/sketch2cad_head.pt --epochs 10 "
    "--width 128 --lr 2e-4 --threads 2 --weights runs/main --eval data/heldout5-l1 "
    "data/heldout5-l3 data/people-l1 data/people-l3 --json runs/head5/scores.json",
    "sketch2cad model-card --tuned runs/head5/scores.json",
]


def pct(x: float | None) -> str:
    return "n/a" if x is None else f"{100 * x:.1f}"


def stored(name: str) -> dict:
    """docs/eval/NAME.json."""
    return json.loads((EVAL / f"{name}.json").read_text())


def _store(name: str, figures: dict) -> None:
    EVAL.mkdir(parents=True, exist_ok=True)
    (EVAL / f"{name}.json").write_text(json.dumps(figures, indent=1) + "\n")


def table1_row(r: dict, ops: tuple[str, ...] = OPS) -> list[str]:
    """An evaluation's paper metrics as cells: classification, then face IoU / curve
    accuracy per operator of `ops`, in %."""
    per = r["per_operator"]
    return [pct(r.get("classification_accuracy"))] + [
        f"{pct(per.get(op, {}).get('face_iou'))} / {pct(per.get(op, {}).get('curve_accuracy'))}"
        for op in ops
    ]


def paper_cells(ops: tuple[str, ...] = OPS) -> list[str]:
    """The paper's Table 1 as cells; "-" for an operator it does not have."""
    return [pct(PAPER_TABLE_1["classification_accuracy"])] + [
        f"{pct(PAPER_TABLE_1['face_iou'][op])} / {pct(PAPER_TABLE_1['curve_accuracy'][op])}"
        if op in PAPER_TABLE_1["face_iou"]
        else "-"
        for op in ops
    ]


def _row(cells: list[str]) -> str:
    return "| " + " | ".join(cells) + " |"


def table1_header(first: list[str], ops: tuple[str, ...] = OPS) -> list[str]:
    cells = first + ["classification"] + [f"{op}: face IoU / curve acc." for op in ops]
    return [_row(cells), "|" + "---|" * len(cells)]


def targets_met(r: dict) -> str:
    """Which of the paper's level-1 figures `r` (an evaluation) reaches, in words."""
    met: list[str] = []
    missed: list[str] = []
    ok = r["classification_accuracy"] >= PAPER_TABLE_1["classification_accuracy"]
    (met if ok else missed).append("classification")
    for metric, name in (("face_iou", "face IoU"), ("curve_accuracy", "curve accuracy")):
        for op in OPS:
            ours = r["per_operator"][op][metric]
            (met if ours >= PAPER_TABLE_1[metric][op] else missed).append(f"{op} {name}")
    return f"met: {', '.join(met) or 'none'}; not met: {', '.join(missed) or 'none'}"


def recovery_cell(d: dict) -> str:
    """Strict recovery [with the named flip], in %."""
    flip = d.get("recovery_rate_with_flip")
    cell = pct(d.get("recovery_rate"))
    return cell if flip is None or d.get("recovery_n") == 0 else f"{cell} [{pct(flip)}]"


def shipped_section() -> list[str]:
    """What ships: each file with its size and SHA-256, the networks' shapes."""
    unet = torch.load(WEIGHTS / WEIGHTS_NAME, map_location="cpu", weights_only=False)
    config = unet["config"]
    rows = [
        _row(["file", "what", "size", "SHA-256"]),
        "|---|---|---|---|",
        _row(
            [
                f"`{WEIGHTS_NAME}`",
                "U-Net: operator classifier, base-face (F) and curve (C) maps",
                f"{(WEIGHTS / WEIGHTS_NAME).stat().st_size / 2**20:.1f} MB",
                f"`{sha256_of(WEIGHTS / WEIGHTS_NAME)}`",
            ]
        ),
    ]
    head_lines = []
    if (WEIGHTS / HEAD_NAME).exists():
        head = torch.load(WEIGHTS / HEAD_NAME, map_location="cpu", weights_only=False)
        rows.append(
            _row(
                [
                    f"`{HEAD_NAME}`",
                    "structured head: each stroke's role and the base face",
                    f"{(WEIGHTS / HEAD_NAME).stat().st_size / 2**20:.1f} MB",
                    f"`{sha256_of(WEIGHTS / HEAD_NAME)}`",
                ]
            )
        )
        head_lines = [
            f"- `{HEAD_NAME}` (`inference/head/`): "
            f"{sum(v.numel() for v in head['model'].values())} parameters "
            f"({json.dumps(head['config'])}). It reads the frozen U-Net's features per "
            "stroke (sampled along the polyline, with its geometry) and per visible face "
            "(pooled over the face-ID map), with a small transformer for the context "
            "between them (its attention biased by how near two strokes' ends lie and by "
            "how much of a stroke lies on a face), and chooses each stroke's role (with the "
            "counts the operator's drawing has: a prism's n start, n profile and n end "
            "strokes, a sweep's 1, 2, 1, a bevel's one l) and the base face; the choices are "
            "painted back into C and F, which the fitting reads. The predictor loads it with "
            "the U-Net beside it and refuses it for any U-Net but the one whose SHA-256 it "
            f"records (`{head['unet_sha256'][:12]}...`).",
        ]
    return [
        "## What ships",
        "In `Sketch2CADWorkbench/inference/weights/`, loaded from disk only:",
        "",
        *rows,
        "",
        f"- `{WEIGHTS_NAME}` (`inference/models.py`): one shared-encoder U-Net over the "
        "sketch S, depth D and normals N (5 channels), pooled from 256x256 to an internal "
        f"{config['internal_size']}x{config['internal_size']}, with the operator classifier "
        f"on the bottleneck and per-operator F and C heads; widths {tuple(config['widths'])}.",
        *head_lines,
        "- `thresholds.json`: the regression guard (below).",
        "",
    ]


def limits_section(pipeline: dict) -> list[str]:
    """Intended use, and what the strokes cannot tell with the bounds the project
    computes (docs/eval/extrusion_bound.json, oracle.json, sessions.json)."""
    bounds = stored("extrusion_bound")
    oracle, sessions = stored("oracle")["sessions"], stored("sessions")
    sets = pipeline["sets"]
    extrude = "; ".join(
        f"{name} (noise level {sets[name]['noise_level']}): at most "
        f"{pct(b['expected_bound'])}% expected, the pipeline "
        f"{pct(sets[name]['per_operator']['extrude']['recovery_rate'])}%"
        for name, b in bounds["sets"].items()
    )
    shells = "; ".join(
        f"{name} (noise level {b['noise_level']}, {b['n']} of {b['drawn']} shells): at most "
        f"{pct(b['expected_bound'])}% expected"
        + (
            f", the pipeline {pct(sets[name]['per_operator']['shell']['recovery_rate'])}%"
            if name in sets
            else ""
        )
        for name, b in bounds.get("shells", {}).get("sets", {}).items()
    )
    ceilings = "; ".join(
        f"{name} {op} {pct(d['strict_ceiling'])}% (the pipeline {recovery_cell(d)})"
        for name, r in sets.items()
        for op, d in r["per_operator"].items()
        if d.get("strict_ceiling") is not None and d["strict_ceiling"] < 1  # a Boolean to read
    )
    rows = [
        _row(
            [
                "session",
                "oracle: final (as read / snapped)",
                "oracle: weakest step, the session so ended",
                "pipeline: final (own choices / regularization off)",
                "pipeline: each step read alone, the session so ended (-: doubtful, not added)",
            ]
        ),
        "|---|---|---|---|---|",
    ]
    short = []
    for name, o in oracle.items():
        p = sessions["sessions"][name]
        rows.append(
            _row(
                [
                    name,
                    f"{o['final_iou']:.3f} / {o['regularized_iou']:.3f}",
                    f"{o['weakest_step']}: {o['weakest_session_iou']:.3f}",
                    f"{p['final_iou']:.3f} / {p['final_iou_regularization_off']:.3f}",
                    # None: the step's reading was doubtful and not added
                    " ".join("-" if x is None else f"{x:.3f}" for x in p["each_step"]),
                ]
            )
        )
        if o["weakest_session_iou"] < SESSION_TARGET:
            short.append(name)
    return [
        "## Intended use",
        "Reading one modeling operation at a time from freehand strokes drawn over a model "
        "in an orthographic view, in the FreeCAD workbench or `sketch2cad interpret`: "
        "extruding a face, beveling or rounding an edge, adding or subtracting a prism, a "
        "sweep, shelling a solid open at a face. The networks saw only synthetic sketches "
        "(`sketch2cad datagen`: random modeling sequences, strokes at noise levels 1 to 3, "
        "1.4%, 2.8% and 4.1% of the image diagonal, drawn by the generator's hand"
        + (
            " and, for the shipped head, by people's: `datagen/hand.py`"
            if (EVAL / "tuned.json").exists()
            else "; people's hand, `datagen/hand.py`, only measured"
        )
        + "); other operations, several operations in one sketch, or photographs of paper "
        "sketches are outside what they were trained and measured on.",
        "",
        "## Limits: what the strokes cannot tell",
        "- A hole and the boss on its rim draw the same lines (paper, Fig. 5b). The "
        "pipeline reads the +/- option by a rule and names the other Boolean as a one-click "
        "flip; `sketch2cad eval --recovery` prints `strict_ceiling`, the most a strict "
        f"reading by the rule can reach: {ceilings}.",
        "- An extrusion's distance is told only by where the strokes end. "
        "`sketch2cad extrusion-bound DATA` (an oracle that knows f, which stroke tip was "
        "drawn at which corner, the generator's noise and its prior on d, taking the d most "
        f"likely to pass the 0.95 test) bounds any reading: {extrude}.",
        *(
            [
                "- A shell's wall thickness is told only by where the rim's corners are "
                "drawn. `sketch2cad extrusion-bound DATA --shells` (the same oracle for t, on "
                "rims of lines) bounds any reading: "
                f"{shells}."
            ]
            if shells
            else []
        ),
        "- Which end face a bevel's l lies on is not in the strokes where both ends face the "
        "viewer alike; the bevel figures move by a few points from set to set.",
        "- Sketch sessions: `sketch2cad oracle --examples` reads each step of the example "
        "sessions knowing the protocol's structure and which stroke draws which curve, its "
        "numbers by least squares on the strokes; each step's reading put alone into the "
        "true protocol says how far its strokes let the session go, the weakest step bounds "
        "it (generously: numbers the strokes do not tell stay the truth's). Final volume IoU "
        "with the protocol each session was drawn from:",
        "",
        *rows,
        "",
        f"No reading that follows the strokes ends {', '.join(short) or 'none'} at "
        f"{SESSION_TARGET} or above: a step's strokes there, read by their likeliest numbers, "
        "end the session below it with every other step exact.",
        "",
    ]


def compute_section() -> list[str]:
    """The data and compute of both networks, and the speed of the pipeline."""
    unet = torch.load(WEIGHTS / WEIGHTS_NAME, map_location="cpu", weights_only=False)
    key, s = unet["data_key"], unet["settings"]
    lines = [
        "## Data and compute",
        f"- U-Net: `sketch2cad datagen` v{key['version']}, {key['count']} samples, seed "
        f"{key['seed']}, noise `{key['noise']}` (levels 1, 2, 3 take turns); "
        f"{unet['trained_steps']} steps of {s['batch_size']} samples "
        f"({unet['trained_epochs']:.2f} epochs) in {unet['trained_minutes']:.0f} min of "
        f"optimisation on {s['threads']} torch threads on `{s['device']}` (2 CPU cores, no "
        "GPU). The loss: the paper's (Eq. 1, class-weighted cross entropy; Eq. 2, F over "
        "the image and C on stroke pixels)"
        + (
            f", plus a soft Dice term on F of weight {s['face_dice']}, so that small base "
            "faces count as much as large ones."
            if s.get("face_dice")
            else "."
        ),
        f"  Settings: {json.dumps({k: v for k, v in s.items() if k != 'model'})}. Loss "
        "curves: `docs/loss_curves.png`.",
    ]
    if (WEIGHTS / HEAD_NAME).exists():
        head = torch.load(WEIGHTS / HEAD_NAME, map_location="cpu", weights_only=False)
        hs = head["settings"]
        tuned = f" from `{hs['init']}` (below)" if hs.get("init") else ""
        lines.append(
            f"- Structured head{', fine-tuned' if tuned else ''}{tuned}: {hs['epochs']} epochs "
            f"of {head['train_samples']} samples "
            f"({_trained_on(head.get('data_counts') or {}, head.get('data'))}) in "
            f"{sum(r['seconds'] for r in head['log']) / 60:.1f} min on {hs['threads']} torch "
            "thread(s), on the frozen U-Net's features (read once into a token cache). "
            f"Settings: {json.dumps({k: v for k, v in hs.items() if k != 'head'})}."
        )
    speed = stored("speed")
    lines += [
        f"- Speed, {speed['about']}: an interpret step (render, networks, fitting, B-rep) "
        f"{speed['interpret']['median_ms']} ms median, 90% within "
        f"{speed['interpret']['p90_ms']} ms (`{speed['interpret']['command']}`); the U-Net "
        f"with the head {speed['networks']['unet_and_head_median_ms']} ms "
        f"(`{speed['networks']['command']}`).",
        "",
    ]
    return lines


def _trained_on(counts: dict, data: str | None) -> str:
    """A head's training data: each set with its count when it trained on several."""
    if len(counts) > 1:
        return "the union of " + ", ".join(f"{n} of `{d}`" for d, n in counts.items())
    return f"`{data}`"


def figures_section(pipeline: dict) -> list[str]:
    """The shipped pipeline's current figures: the paper's metrics of the readings the
    fitting gets, and recovery per held-out set."""
    sets = pipeline["sets"]
    metrics = table1_header(["data", "n", "reading"], HEAD_OPS)
    for name, r in sets.items():
        if "structured" in r:
            if "face_iou" in r["per_operator"]["extrude"]:
                metrics.append(_row([name, str(r["n"]), "U-Net alone", *table1_row(r, HEAD_OPS)]))
            metrics.append(
                _row(
                    [
                        name,
                        str(r["structured"].get("n", r["n"])),
                        "U-Net and head (shipped)",
                        *table1_row(r["structured"], HEAD_OPS),
                    ]
                )
            )
    metrics.append(_row(["paper, Table 1 (level 1)", "", "", *paper_cells(HEAD_OPS)]))
    name1, level1 = next(
        (k, r) for k, r in sets.items() if r["noise_level"] == 1 and "structured" in r
    )
    recovery = [
        _row(
            [
                "data",
                "hand",
                "base faces",
                "noise level",
                "n",
                "regularization",
                *HEAD_OPS,
                "operator read",
            ]
        ),
        "|---|---|---|---|---|---|" + "---|" * (len(HEAD_OPS) + 1),
    ]
    for name, r in sets.items():
        recovery.append(
            _row(
                [
                    name,
                    r.get("hand", "generator"),
                    "curved" if r["curved"] else "planar",
                    str(r["noise_level"]),
                    str(r["n"]),
                    "on" if r["regularize"] else "off",
                    *(
                        recovery_cell(r["per_operator"][op])
                        if r["per_operator"].get(op, {}).get("recovery_rate") is not None
                        else "-"
                        for op in HEAD_OPS
                    ),
                    pct(r.get("operator_read_rate")),
                ]
            )
        )
    return [
        "## The shipped pipeline's figures",
        f"{pipeline['about'][0].upper()}{pipeline['about'][1:]}. Each set: how it was made "
        "and the commands that printed its figures are in `docs/eval/pipeline.json`.",
        "",
        "The paper's metrics (Table 1: classification accuracy, face IoU and curve "
        "accuracy on the ground-truth operator's maps), %; the head's choices are scored "
        "painted into F and C, since they are what the fitting reads:",
        "",
        *metrics,
        "",
        f"Against the paper's level-1 figures, on {name1}: {targets_met(level1['structured'])}.",
        "",
        "Recovery of whole interpret steps, strict [with the named flip], %, and the "
        "share of the steps read as the operator drawn (five classes, the shell "
        "included; n/a: not measured)"
        + (
            "; curved base faces are cylinders' and cones' sides:"
            if any(r["curved"] for r in sets.values())
            else ":"
        ),
        "",
        *recovery,
        "",
    ]


def unet_section(unet: dict) -> list[str]:
    rows = table1_header(["noise level", "n"])
    rows[0] = rows[0][:-1] + "| networks ms |"
    rows[1] += "---|"
    for level, r in sorted(unet["levels"].items()):
        rows.append(
            _row([level, str(r["n"]), *table1_row(r), f"{r['latency_ms']['networks_median']:.1f}"])
        )
    return [
        "## The U-Net alone",
        f"{unet['about'][0].upper()}{unet['about'][1:]} (`{unet['commands'][-1]}`), %; the "
        "networks' median latency on 2 CPU threads:",
        "",
        *rows,
        "",
        "Pictures of its maps: `docs/eval-l1.png`, `docs/eval-l2.png`, `docs/eval-l3.png`; "
        "recovery with the U-Net alone, as bars: `docs/recovery.png`.",
        "",
    ]


def heads_section(heads: dict, tuned: bool = False) -> list[str]:
    """The structured heads' ablation: each head trained (its size and training), and per
    held-out set the U-Net's own maps (once) and each head's choices, scored on the same
    samples with the paper's metrics; the end-to-end table when stored."""
    trained, rows = [], []
    first = " (fine-tuned into the shipped head, below)" if tuned else " (shipped)"
    for k, run in enumerate(heads["runs"]):
        h = run["head"]
        label = f"head, {h['layers']} attention layers, width {h['width']}"
        threads = f" on {h['threads']} torch thread(s)" if "threads" in h else ""
        trained.append(
            f"- {label}{first if k == 0 else ''}: {h['parameters']} parameters "
            f"({json.dumps(h['config'])}); {h['epochs']} epochs of {h['train_samples']} "
            f"samples of {_trained_on(h.get('data_counts') or {}, h.get('data'))} in "
            f"{h['minutes']:.1f} min{threads}"
        )
        for data, result in run["scores"].items():
            for name in ("unet", "head"):
                if name in result:
                    rows.append((data, label if name == "head" else "U-Net alone", result[name]))
    table = table1_header(["data", "n", "reading"])
    for data, name, r in sorted(rows, key=lambda row: row[0]):
        table.append(_row([Path(data).name, str(r["n"]), name, *table1_row(r)]))
    table.append(_row(["paper, Table 1 (level 1)", "", "", *paper_cells()]))
    return [
        "## Structured heads: the ablation",
        f"The head {'the shipped one was fine-tuned from' if tuned else 'that ships'} and "
        "the same head without context (no attention layers), trained on the same samples; "
        "%, printed by:",
        "",
        *(f"    {c}" for c in heads["commands"]),
        "",
        *trained,
        "",
        *table,
        "",
        *(end_to_end(heads["end_to_end"]) if heads.get("end_to_end") else []),
    ]


def tuned_section(tuned: dict) -> list[str]:
    """The shipped head, fine-tuned from the ablation's first: its training and its
    figures beside the U-Net's on the held-out sets it was scored on."""
    h = tuned["head"]
    table = table1_header(["data", "n", "reading"], HEAD_OPS)
    for data, r in sorted(tuned["scores"].items()):
        name = Path(data).name
        table.append(
            _row([name, str(r["unet"]["n"]), "U-Net alone", *table1_row(r["unet"], HEAD_OPS)])
        )
        table.append(
            _row([name, str(r["head"]["n"]), "head (shipped)", *table1_row(r["head"], HEAD_OPS)])
        )
    return [
        "## The shipped head: five operators, two hands",
        f"The ablation's first head (`{h['init']}`) fine-tuned for {h['epochs']} epochs of "
        f"{h['train_samples']} samples ({_trained_on(h['data_counts'], h.get('data'))}) in "
        f"{h['minutes']:.1f} min on {h['threads']} torch thread(s): shells and rounds, the "
        "generator's hand and people's (outlines in one stroke, curves split, traced over or "
        "left open, hidden lines left out), each sketch's strokes cut and joined into pieces "
        "of curves as `interpret` reads them. It classifies five operators, the shell "
        "among them; the U-Net alone, four, and is scored on the samples of those. %, "
        "printed by:",
        "",
        *(f"    {c}" for c in tuned["commands"]),
        "",
        *table,
        "",
    ]


def end_to_end(recovery: dict[str, dict]) -> list[str]:
    """Recovery of whole interpret steps with the U-Net alone and with the head, per
    data set (`sketch2cad head-recovery --json`), strict [with the flip]."""
    out = [
        "End to end (`sketch2cad head-recovery`; interpret, regularization off; recovered: "
        "volume IoU >= 0.95 with the truth; in brackets with the named one-click flip of the "
        "Boolean), %; interpret ms is wall time, comparable only between rows run at the "
        "same load:",
        "",
        _row(["data", "reading", *(f"{op} (n)" for op in OPS), "interpret ms (median)"]),
        "|---|---|" + "---|" * len(OPS) + "---|",
    ]
    for data, rows in recovery.items():
        for name, r in rows.items():
            per = r["per_operator"]
            out.append(
                _row(
                    [
                        data,
                        name,
                        *(f"{recovery_cell(per[op])} ({per[op]['recovery_n']})" for op in OPS),
                        f"{r['interpret_median_ms']:.0f}",
                    ]
                )
            )
    return out + [""]


def reproduce_section(pipeline: dict) -> list[str]:
    sets = pipeline["sets"]
    return [
        "## How to reproduce",
        "The weights: `make weights` (data, 90 min of training on 2 CPU cores, evaluation, "
        "the structured heads, this card), that is:",
        "```",
        *UNET_COMMANDS,
        *HEAD_COMMANDS,
        *(TUNED_COMMANDS if (EVAL / "tuned.json").exists() else []),
        "```",
        "The figures above: each held-out set made and measured by",
        "```",
        *(c for r in sets.values() for c in (r["made_by"], *r["commands"])),
        stored("extrusion_bound")["command"],
        *(
            [stored("extrusion_bound")["shells"]["command"]]
            if "shells" in stored("extrusion_bound")
            else []
        ),
        stored("oracle")["command"],
        *stored("sessions")["commands"].values(),
        stored("speed")["interpret"]["command"],
        stored("speed")["networks"]["command"],
        "```",
        "then the figures they print stored in `docs/eval/*.json` and this card written from "
        "them by `sketch2cad model-card`.",
        "",
    ]


def guard_section() -> list[str]:
    return [
        "## Regression guard",
        "`thresholds.json`: the U-Net's level-1 figures less "
        f"{MARGIN_CLASSIFICATION} (classification) and {MARGIN_SEGMENTATION} (face IoU, "
        "curve accuracy); `tests/inference/test_shipped_weights.py` evaluates these weights "
        "on 96 freshly generated samples (seed 9090) against them.",
    ]


def card() -> str:
    """The whole model card, from the shipped files and docs/eval/."""
    pipeline = stored("pipeline")
    lines = [
        "# Model card: Sketch2CAD's networks",
        "",
        "Written by `sketch2cad model-card` from the shipped files and the figures stored in "
        "`docs/eval/` (each with the command that printed it); do not edit by hand.",
        "",
        *shipped_section(),
        *limits_section(pipeline),
        *compute_section(),
        *figures_section(pipeline),
        *unet_section(stored("unet")),
        *(
            heads_section(stored("heads"), (EVAL / "tuned.json").exists())
            if (EVAL / "heads.json").exists()
            else []
        ),
        *(tuned_section(stored("tuned")) if (EVAL / "tuned.json").exists() else []),
        *reproduce_section(pipeline),
        *guard_section(),
    ]
    return "\n".join(lines) + "\n"


def head_summary(head: dict) -> dict:
    """What the card says of a head, from its checkpoint (`sketch2cad train-head`)."""
    return {
        "layers": head["config"]["layers"],
        "width": head["config"].get("width"),
        "parameters": sum(v.numel() for v in head["model"].values()),
        "config": head["config"],
        "epochs": head["settings"]["epochs"],
        "train_samples": head.get("train_samples"),
        "data": head.get("data"),
        "data_counts": head.get("data_counts") or {},
        "minutes": round(sum(r["seconds"] for r in head["log"]) / 60, 1),
        "threads": head["settings"]["threads"],
        "unet_sha256": head.get("unet_sha256"),
    }


def _head_beside(scores: Path) -> dict:
    """The head checkpoint in the scores' run folder.

    Raises:
        FileNotFoundError: naming it, when there is none.
    """
    path = scores.parent / HEAD_NAME
    if not path.exists():
        raise FileNotFoundError(f"{path}: no head beside {scores}")
    return torch.load(path, map_location="cpu", weights_only=False)


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
    for ax, level in zip(np.atleast_1d(axes), levels, strict=True):
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


def add_arguments(ap: argparse.ArgumentParser) -> None:
    ap.add_argument(
        "--run",
        type=Path,
        help="training run folder (with --eval): ship its U-Net and store its figures",
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
        "checkpoint beside each), the shipped or shipping head first: store the ablation",
    )
    ap.add_argument(
        "--head-recovery",
        type=Path,
        nargs="+",
        metavar="JSON",
        help="`sketch2cad head-recovery --json` results: the heads' end-to-end table",
    )
    ap.add_argument(
        "--tuned",
        type=Path,
        metavar="JSON",
        help="`sketch2cad train-head --init --json` scores of a head fine-tuned from the "
        "ablation's first: ship the head beside them and store its figures",
    )
    ap.add_argument(
        "--ship-head",
        action="store_true",
        help=f"copy the first --heads run's {HEAD_NAME} beside the shipped "
        "U-Net (it must have been trained on that U-Net's features)",
    )


def _error(text: str) -> int:
    print(f"sketch2cad model-card: error: {text}", file=sys.stderr)
    return 2


def run(args: argparse.Namespace) -> int:
    if (args.run is None) != (args.eval is None):
        return _error("give --run with --eval (a new U-Net), or neither")
    if (args.ship_head or args.head_recovery) and not args.heads:
        return _error("--ship-head and --head-recovery go with --heads")
    evals = {}
    for item in args.eval or []:
        level, _, path = item.partition("=")
        evals[level] = json.loads(Path(path).read_text())
    if args.run is not None and "1" not in evals:
        return _error("the level-1 evaluation sets the thresholds: pass 1=JSON")
    try:
        heads = [(json.loads(p.read_text()), _head_beside(p)) for p in args.heads or []]
        recovery = {p.stem: json.loads(p.read_text()) for p in args.head_recovery or []}
        if args.run is not None:
            _ship_unet(args.run, evals)
        if heads:
            _ship_heads(heads, recovery, args.ship_head, args.heads[0].parent / HEAD_NAME)
        if args.tuned is not None:
            _ship_tuned(args.tuned)
    except (FileNotFoundError, ValueError) as e:
        return _error(str(e))
    (WEIGHTS / "MODEL_CARD.md").write_text(card())
    print(f"wrote {WEIGHTS / 'MODEL_CARD.md'}")
    return 0


def _ship_unet(run_dir: Path, evals: dict[str, dict]) -> None:
    """The run's U-Net copied into the package with its thresholds, its figures stored,
    a head trained on another U-Net dropped, and the pictures drawn."""
    ckpt = torch.load(run_dir / WEIGHTS_NAME, map_location="cpu", weights_only=False)
    WEIGHTS.mkdir(exist_ok=True)
    shutil.copyfile(run_dir / WEIGHTS_NAME, WEIGHTS / WEIGHTS_NAME)
    _drop_stale_head()
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
    _store(
        "unet",
        {
            "about": "the U-Net alone, its own maps, on the test sets it was evaluated on "
            "when trained",
            "commands": UNET_COMMANDS[1:],
            "levels": {
                level: {
                    "n": r["n"],
                    "classification_accuracy": r["classification_accuracy"],
                    "per_operator": {
                        op: {k: r["per_operator"][op][k] for k in ("face_iou", "curve_accuracy")}
                        for op in OPS
                    },
                    "latency_ms": {"networks_median": r["latency_ms"]["networks_median"]},
                }
                for level, r in evals.items()
            },
        },
    )
    s = ckpt["settings"]
    plot_curves(run_dir / "log.jsonl", ROOT / "docs" / "loss_curves.png", s.get("face_dice", 0.0))
    plot_recovery(evals, ROOT / "docs" / "recovery.png")


def _ship_heads(
    heads: list[tuple[dict, dict]], recovery: dict[str, dict], ship: bool, first: Path
) -> None:
    """The heads' figures stored; with `ship`, the first head (file `first`) copied
    beside the shipped U-Net.

    Raises:
        ValueError: for a head trained on another U-Net's features.
    """
    if ship:
        if heads[0][1].get("unet_sha256") != sha256_of(WEIGHTS / WEIGHTS_NAME):
            raise ValueError(
                f"{first}: not a head trained on the features of {WEIGHTS / WEIGHTS_NAME}"
            )
        shutil.copyfile(first, WEIGHTS / HEAD_NAME)
    runs = []
    for k, (scores, head) in enumerate(heads):
        runs.append(
            {
                "head": head_summary(head),
                "scores": {
                    data: {n: r[n] for n in (("unet", "head") if k == 0 else ("head",)) if n in r}
                    for data, r in scores.items()
                },
            }
        )
    figures = {"commands": HEAD_COMMANDS[4:6], "runs": runs}
    if recovery:
        figures["end_to_end"] = recovery
    _store("heads", figures)


def _ship_tuned(scores: Path) -> None:
    """The fine-tuned head beside `scores` copied beside the shipped U-Net, its figures
    stored (docs/eval/tuned.json).

    Raises:
        ValueError: for a head trained on another U-Net's features.
    """
    head = _head_beside(scores)
    if head.get("unet_sha256") != sha256_of(WEIGHTS / WEIGHTS_NAME):
        raise ValueError(f"{scores.parent / HEAD_NAME}: trained on another U-Net's features")
    shutil.copyfile(scores.parent / HEAD_NAME, WEIGHTS / HEAD_NAME)
    _store(
        "tuned",
        {
            "commands": TUNED_COMMANDS[-2:-1],
            "head": {**head_summary(head), "init": head["settings"].get("init")},
            "scores": json.loads(scores.read_text()),
        },
    )


def _drop_stale_head() -> None:
    """Remove a shipped head that another U-Net's features trained: the predictor would
    refuse it (the new U-Net's card says whether a head for it ships)."""
    path = WEIGHTS / HEAD_NAME
    if path.exists() and torch.load(path, map_location="cpu", weights_only=False).get(
        "unet_sha256"
    ) != sha256_of(WEIGHTS / WEIGHTS_NAME):
        path.unlink()
        print(f"removed {path}: trained on another U-Net's features")
