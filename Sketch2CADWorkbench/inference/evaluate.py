# SPDX-License-Identifier: LGPL-2.1-or-later
"""Evaluation: `sketch2cad eval --data DIR [--weights DIR] --json OUT.json [--report OUT.png]`.

The paper's network metrics (Sec. 6, Tables 1-2), on a data set the networks were not
trained on, all at the full 256 x 256 size that the fitting stage reads:

classification accuracy
    argmax of the class probabilities against the ground-truth operator, over all
    samples; the confusion matrix has rows = truth, columns = prediction.
face IoU (per operator)
    for each sample of that (ground-truth) operator, with F the base-face map of the
    ground-truth operator's head (the paper evaluates each segmentation network on its
    own operator, whatever the classifier says):
        P = {F > 0.5}, G = {F~ > 0.5},  IoU = |P and G| / |P or G|  (1 when both are empty),
    then the mean over the samples. `face_iou_pooled` adds sum |P and G| / sum |P or G|.
curve accuracy (per operator)
    the predicted class of a stroke pixel is the number of thresholds its C exceeds
    (0.5 for extrude and bevel; 0.5 and 1.5 for add/sub and sweep, as the paper's
    C > 0.5 / C <= 0.5 split); the accuracy is the fraction of all stroke pixels (M~)
    of that operator's samples whose class equals C~. `curve_accuracy_per_sample` adds
    the mean of the per-sample fractions.
latency
    the median wall time of `predict` (pooling, network, upsampling of every output to
    256 x 256) on one sketch (batch 1) at 2 threads, over the first samples.
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import torch
from tqdm import tqdm

from ..sketch.labels import CLASSES, CURVE_THRESHOLDS
from datagen.dataset import Dataset, decode_inputs

NAMES = [c.value for c in CLASSES]
# Curve class thresholds per operator index; a pixel's class = how many its C exceeds.
THRESHOLDS = torch.tensor([CURVE_THRESHOLDS[c] for c in CLASSES])
# The paper's Table 1 ("ours"): face IoU and curve accuracy per operator.
PAPER = {"extrude": (0.9178, 0.9804), "bevel": (0.9173, 0.9812), "addsub": (0.7826, 0.9354),
         "sweep": (0.7834, 0.9557)}
LATENCY_THREADS = 2
EXAMPLES_PER_OP = 2


# ---------------------------------------------------------------- metrics
def face_overlap(face_prob: torch.Tensor, face_label: torch.Tensor
                 ) -> tuple[torch.Tensor, torch.Tensor]:
    """|P and G| and |P or G| per sample, P = {F > 0.5}, G = {F~ > 0.5}.

    Args:
        face_prob: (B, H, W) predicted F in 0..1; face_label: (B, H, W) F~.
    Returns:
        intersection and union pixel counts, (B,) int64 each.
    """
    p, g = face_prob > 0.5, face_label > 0.5
    return (p & g).sum((1, 2)), (p | g).sum((1, 2))


def face_iou(face_prob: torch.Tensor, face_label: torch.Tensor) -> torch.Tensor:
    """(B,) IoU of {F > 0.5} and {F~ > 0.5}; 1 where both are empty."""
    inter, union = face_overlap(face_prob, face_label)
    return torch.where(union > 0, inter / union.clamp(min=1), 1.0)


def curve_classes(curve: torch.Tensor, op: torch.Tensor) -> torch.Tensor:
    """(B, H, W) C values -> (B, H, W) int64 classes under operator op's thresholds (B,)."""
    t = THRESHOLDS.to(curve.device)[op]                                   # (B, 2)
    return (curve[:, None] > t[:, :, None, None]).sum(1)


def curve_hits(curve: torch.Tensor, curve_label: torch.Tensor, stroke_mask: torch.Tensor,
               op: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """Stroke pixels whose predicted class equals C~, and all stroke pixels, per sample.

    Args:
        curve: (B, H, W) predicted C; curve_label: (B, H, W) C~; stroke_mask: (B, H, W) M~;
        op: (B,) the operator whose encoding C uses.
    Returns:
        (B,) int64 correct counts and (B,) int64 stroke pixel counts.
    """
    m = stroke_mask > 0.5
    right = (curve_classes(curve, op) == curve_label.round().long()) & m
    return right.sum((1, 2)), m.sum((1, 2))


@dataclass
class Tally:
    """Per-sample results, summed up into the metrics' JSON (`summary`)."""

    rows: list[torch.Tensor] = field(default_factory=list)

    def add(self, op, pred, noise, inter, union, right, strokes) -> None:
        """Each argument (B,): truth, predicted class, noise level, face intersection and
        union, correct and total stroke pixels."""
        self.rows.append(torch.stack([torch.as_tensor(v).long().cpu() for v in
                                      (op, pred, noise, inter, union, right, strokes)], 1))

    def summary(self) -> dict:
        r = torch.cat(self.rows) if self.rows else torch.zeros(0, 7, dtype=torch.long)
        op, pred, noise, inter, union, right, strokes = r.T
        confusion = torch.zeros(4, 4, dtype=torch.long)
        confusion.index_put_((op, pred), torch.ones_like(op), accumulate=True)
        iou = torch.where(union > 0, inter / union.clamp(min=1), 1.0)
        frac = torch.where(strokes > 0, right / strokes.clamp(min=1), 1.0)

        def group(sel: torch.Tensor) -> dict:
            k = int(sel.sum())
            if not k:
                return {"n": 0, "face_iou": None, "curve_accuracy": None}
            return {"n": k, "face_iou": float(iou[sel].mean()),
                    "curve_accuracy": float(right[sel].sum() / strokes[sel].sum().clamp(min=1)),
                    "face_iou_pooled": float(inter[sel].sum() / union[sel].sum().clamp(min=1)),
                    "curve_accuracy_per_sample": float(frac[sel].mean())}

        def accuracy(sel: torch.Tensor) -> float | None:
            return float((op[sel] == pred[sel]).float().mean()) if sel.any() else None

        levels = sorted(int(v) for v in noise.unique())
        return {
            "n": len(op),
            "classification_accuracy": accuracy(torch.ones_like(op, dtype=torch.bool)),
            "per_operator": {name: group(op == k) for k, name in enumerate(NAMES)},
            "confusion_matrix": {"classes": NAMES, "rows_true_cols_predicted": confusion.tolist()},
            "per_noise_level": {str(lv): {"classification_accuracy": accuracy(noise == lv),
                                          **{name: group((noise == lv) & (op == k))
                                             for k, name in enumerate(NAMES)}}
                                for lv in levels},
        }


# ---------------------------------------------------------------- the command's work
def latency_ms(model, inputs: list[np.ndarray], threads: int = LATENCY_THREADS) -> float:
    """Median ms of model.predict on one (5, S, S) sketch at a time, `threads` threads."""
    before = torch.get_num_threads()
    torch.set_num_threads(threads)
    model.predict(torch.from_numpy(inputs[0])[None])  # first call allocates
    times = []
    for x in inputs:
        t = time.perf_counter()
        model.predict(torch.from_numpy(x)[None])
        times.append(1e3 * (time.perf_counter() - t))
    torch.set_num_threads(before)
    return statistics.median(times)


def evaluate(data: Path, weights: Path | None = None, limit: int | None = None,
             latency_runs: int = 50, batch: int = 32) -> tuple[dict, list[dict]]:
    """The metrics of the JSON and a few example predictions for the report.

    Args:
        data: data set folder; weights: file or folder (None: the shipped weights);
        limit: use the first `limit` samples only; latency_runs: sketches timed one by
        one; batch: samples per forward pass for the metrics (the outputs do not depend
        on it: batch norm uses its running statistics at inference).
    Returns:
        the result dictionary and example predictions (numpy maps per sample).
    """
    from .weights import load_model, resolve
    path = resolve(weights)
    model, ckpt = load_model(path)
    ds = Dataset(data)
    n_total = min(len(ds), limit) if limit else len(ds)
    if n_total == 0:
        raise ValueError(f"{data}: the data set has no complete shard yet")
    tally, examples, timed = Tally(), [], []
    done = 0
    with tqdm(total=n_total, desc="eval", unit="sample", leave=False) as bar:
        for k in ds.shards:
            a = ds.shard_arrays(k)
            m = min(len(a["op_type"]), n_total - done)
            for i in range(0, m, batch):
                sl = slice(i, min(i + batch, m))
                x = decode_inputs(a, sl)                                       # (B, 5, S, S)
                probs, f, c = model.predict(torch.from_numpy(x))
                op = torch.from_numpy(a["op_type"][sl].astype(np.int64))
                face = torch.from_numpy(a["face_label"][sl].astype(np.float32))
                curve = torch.from_numpy(a["curve_label"][sl].astype(np.float32))
                mask = torch.from_numpy(a["stroke_mask"][sl].astype(np.float32))
                rows = torch.arange(len(op))
                fo, co = f[rows, op], c[rows, op]       # the true operator's maps (B, S, S)
                tally.add(op, probs.argmax(1), torch.from_numpy(a["noise_level"][sl]),
                          *face_overlap(fo, face), *curve_hits(co, curve, mask, op))
                for j in range(len(op)):
                    if len(timed) < latency_runs:
                        timed.append(x[j])
                    if sum(e["op"] == int(op[j]) for e in examples) < EXAMPLES_PER_OP:
                        examples.append({"op": int(op[j]), "pred": int(probs[j].argmax()),
                                         "sketch": x[j, 0], "depth": x[j, 1],
                                         "face": fo[j].numpy(), "face_label": face[j].numpy(),
                                         "curve": co[j].numpy(), "curve_label": curve[j].numpy(),
                                         "mask": mask[j].numpy()})
                bar.update(len(op))
            done += m
            if done >= n_total:
                break
    result = tally.summary()
    result["latency_ms"] = {"networks_median": latency_ms(model, timed),
                            "runs": len(timed), "threads": LATENCY_THREADS}
    result["data"] = {"path": str(data), "seed": ds.manifest.get("seed"),
                      "noise": ds.manifest.get("noise")}
    result["weights"] = {"path": str(path), "config": ckpt["config"],
                         "trained_on": ckpt.get("data_key")}
    trained = ckpt.get("data_key") or {}
    if trained.get("seed") == ds.manifest.get("seed") and trained.get("count") == len(ds):
        print(f"sketch2cad eval: warning: {data} looks like the training data set (same seed "
              "and size); generate a held-out set with another --seed", file=sys.stderr)
    order = sorted(range(len(examples)), key=lambda e: examples[e]["op"])
    return result, [examples[e] for e in order]


# ---------------------------------------------------------------- the picture
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
    cm = np.array(result["confusion_matrix"]["rows_true_cols_predicted"])
    ax.imshow(cm / np.maximum(cm.sum(1, keepdims=True), 1), cmap="Blues", vmin=0, vmax=1)
    for i in range(4):
        for j in range(4):
            ax.text(j, i, str(cm[i, j]), ha="center", va="center")
    ax.set_xticks(range(4), NAMES)
    ax.set_yticks(range(4), NAMES)
    ax.set(xlabel="predicted", ylabel="true",
           title=f"classification accuracy {result['classification_accuracy']:.4f} "
                 f"(n = {result['n']})")
    ax = fig.add_subplot(grid[0, 2:])
    x = np.arange(4)
    per = result["per_operator"]
    for dx, values, label, alpha in (
            (-0.3, [per[n]["face_iou"] or 0 for n in NAMES], "face IoU", 1.0),
            (-0.1, [PAPER[n][0] for n in NAMES], "face IoU, paper", 0.4),
            (0.1, [per[n]["curve_accuracy"] or 0 for n in NAMES], "curve accuracy", 1.0),
            (0.3, [PAPER[n][1] for n in NAMES], "curve accuracy, paper", 0.4)):
        bars = ax.bar(x + dx, values, 0.2, label=label, alpha=alpha)
        ax.bar_label(bars, fmt="%.3f", fontsize=6)
    ax.set_xticks(x, [f"{n} (n={per[n]['n']})" for n in NAMES])
    ax.set(ylim=(0, 1.08), title=f"per operator; networks {result['latency_ms']['networks_median']:.1f}"
                                 " ms per sketch (median, batch 1, 2 threads)")
    ax.legend(fontsize=7, loc="lower left")
    curves = ListedColormap(["#1f77b4", "#d62728", "#2ca02c"])
    for r, e in enumerate(examples, start=1):
        panels = [
            ("sketch over D", np.dstack([np.maximum(e["depth"], e["sketch"])] * 2
                                        + [e["depth"] * (1 - e["sketch"])]), {}),
            ("F (ours)", e["face"], {"cmap": "gray", "vmin": 0, "vmax": 1}),
            ("F~", e["face_label"], {"cmap": "gray", "vmin": 0, "vmax": 1}),
            ("C class on strokes (ours)", np.ma.masked_where(
                e["mask"] < 0.5, curve_classes(torch.from_numpy(e["curve"])[None],
                                               torch.tensor([e["op"]]))[0].numpy()),
             {"cmap": curves, "vmin": 0, "vmax": 2, "interpolation": "nearest"}),
            ("C~", np.ma.masked_where(e["mask"] < 0.5, e["curve_label"]),
             {"cmap": curves, "vmin": 0, "vmax": 2, "interpolation": "nearest"})]
        for col, (title, img, kw) in enumerate(panels):
            ax = fig.add_subplot(grid[r, col])
            ax.imshow(img, **kw)
            ax.set_xticks([])
            ax.set_yticks([])
            if col == 0:
                title = f"{NAMES[e['op']]} (read as {NAMES[e['pred']]})"
            elif col == 1:
                iou = face_iou(torch.from_numpy(e["face"])[None],
                               torch.from_numpy(e["face_label"])[None])[0]
                title += f", IoU {float(iou):.3f}"
            ax.set_title(title, fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


# ---------------------------------------------------------------- command line
def has_ground_truth(data: Path) -> bool:
    """Whether the data set's shards keep each sample's context and operation."""
    ds = Dataset(data)
    return bool(ds.shards) and "context" in ds.shard_meta(ds.shards[0])[0]


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("eval",
                       description="Classification accuracy, per-operator face IoU and curve "
                                   "accuracy, and latency of the networks (paper, Table 1).")
    p.add_argument("--data", type=Path, required=True, help="data set folder (held out)")
    p.add_argument("--weights", type=Path,
                   help="weights file, or a run folder holding sketch2cad_net.pt "
                        "(default: the weights shipped in the package)")
    p.add_argument("--json", type=Path, required=True, help="write the metrics here")
    p.add_argument("--report", type=Path, help="also draw them into this PNG")
    p.add_argument("--limit", type=int, help="use the first LIMIT samples only")
    p.add_argument("--latency-runs", type=int, default=50,
                   help="sketches timed one by one (default %(default)s)")
    p.add_argument("--recovery", type=int, default=200, metavar="N",
                   help="run the whole interpret pipeline on the first N samples for the "
                        "end-to-end recovery rate (0 skips it; default %(default)s)")
    p.add_argument("--fitting-recovery", action="store_true",
                   help="also the recovery rate of the fitting stage alone, given the "
                        "ground-truth operator, F and C (tells network from fitting errors)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    try:
        result, examples = evaluate(args.data, args.weights, args.limit, args.latency_runs)
        if args.recovery and not has_ground_truth(args.data):
            print(f"sketch2cad eval: warning: {args.data} stores no ground-truth operations; "
                  "the end-to-end recovery is skipped", file=sys.stderr)
        elif args.recovery:
            from .recovery import recovery
            from .weights import load_predictor
            rec = recovery(args.data, load_predictor(args.weights), args.recovery)
            for op, v in rec["per_operator"].items():
                result["per_operator"][op].update(v)
            result["latency_ms"]["interpret_median"] = rec["interpret_median_ms"]
            result["recovery"] = {k: rec[k] for k in ("per_noise_level", "failure_reasons")}
            if args.fitting_recovery:
                fit = recovery(args.data, None, args.recovery, oracle=True)
                for op, v in fit["per_operator"].items():
                    result["per_operator"][op]["fitting_recovery_rate"] = v["recovery_rate"]
                    result["per_operator"][op]["fitting_recovery_rate_with_flip"] = \
                        v["recovery_rate_with_flip"]
                result["fitting_recovery"] = {k: fit[k] for k in ("per_noise_level",
                                                                  "failure_reasons")}
    except (FileNotFoundError, ValueError) as e:
        print(f"sketch2cad eval: error: {e}", file=sys.stderr)
        return 2
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps(result, indent=1) + "\n")
    if args.report:
        report(result, examples, args.report)
    print(json.dumps({k: result[k] for k in ("n", "classification_accuracy", "per_operator",
                                            "latency_ms")}, indent=1))
    return 0
