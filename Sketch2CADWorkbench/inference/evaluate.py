# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad eval`: the paper's network metrics, end-to-end recovery, and latency.

Metrics (paper, Sec. 6.2), per sample then averaged per operator:
  face IoU        |{F > 0.5} and {F~ > 0.5}| / |{F > 0.5} or {F~ > 0.5}| of the ground-truth
                  operator's F (1 when both are empty);
  curve accuracy  the share of stroke pixels (M~) whose class from C (thresholds 0.5, and
                  1.5 for add/sub and sweep) equals C~;
  recovery rate   the share of samples whose interpreted operation, applied to the
                  sample's context solid, gives a solid within volume IoU >= 0.95 of the
                  ground truth (the whole pipeline: render, networks, fitting, B-rep).
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

import numpy as np
import torch
from tqdm import tqdm

from ..brep.compare import volume_iou
from ..brep.faces import OperationError
from ..brep.operators import apply_operation, replay
from ..brep.protocol import OperatorType
from ..datagen.dataset import Dataset
from ..datagen.sample import Sample
from .weights import NetworkPredictor, load_predictor

CLASSES = list(OperatorType)
THRESHOLDS = {OperatorType.EXTRUDE: (0.5,), OperatorType.BEVEL: (0.5,),
              OperatorType.ADDSUB: (0.5, 1.5), OperatorType.SWEEP: (0.5, 1.5)}
RECOVERY_IOU = 0.95


def face_iou(face_prob: np.ndarray, face_label: np.ndarray) -> float:
    p, g = face_prob > 0.5, face_label > 0.5
    union = np.logical_or(p, g).sum()
    return 1.0 if union == 0 else float(np.logical_and(p, g).sum() / union)


def curve_accuracy(curve: np.ndarray, curve_label: np.ndarray, stroke_mask: np.ndarray,
                   op: OperatorType) -> float:
    m = stroke_mask > 0
    if not m.any():
        return 1.0
    pred = np.searchsorted(np.asarray(THRESHOLDS[op]), curve[m], side="left")
    return float((pred == np.round(curve_label[m]).astype(int)).mean())


def network_metrics(predictor: NetworkPredictor, samples: list[Sample]) -> dict:
    """Classification, confusion matrix, face IoU and curve accuracy over samples."""
    confusion = np.zeros((4, 4), int)
    per_op = {op: {"iou": [], "acc": []} for op in CLASSES}
    latency = []
    for s in tqdm(samples, desc="networks", unit="sample", leave=False):
        x = s.inputs()
        t = time.perf_counter()
        probs = predictor.classify(x)
        latency.append(1e3 * (time.perf_counter() - t))
        confusion[CLASSES.index(s.op_type), int(np.argmax(probs))] += 1
        f, c = predictor.segment(x, s.op_type)
        per_op[s.op_type]["iou"].append(face_iou(f, s.face_label))
        per_op[s.op_type]["acc"].append(curve_accuracy(c, s.curve_label, s.stroke_mask, s.op_type))
    return {
        "n": len(samples),
        "classification_accuracy": float(np.trace(confusion) / max(confusion.sum(), 1)),
        "confusion_matrix": {"classes": [c.value for c in CLASSES],
                             "rows_true_cols_predicted": confusion.tolist()},
        "per_operator": {op.value: {"n": len(v["iou"]),
                                    "face_iou": float(np.mean(v["iou"])) if v["iou"] else None,
                                    "curve_accuracy": float(np.mean(v["acc"])) if v["acc"] else None}
                         for op, v in per_op.items()},
        "latency_ms": {"networks_median": float(statistics.median(latency)) if latency else None},
    }


def recovery(predictor: NetworkPredictor, samples: list[Sample]) -> dict:
    """End-to-end recovery rate per operator and the median interpret latency."""
    from ..render.maps import MapRenderer
    from .interpret import InterpretError, interpret
    renderer = MapRenderer()
    hits = {op: [] for op in CLASSES}
    times = []
    for s in tqdm(samples, desc="interpret", unit="sample", leave=False):
        context = replay(s.context)[-1]
        try:
            truth = apply_operation(context, s.operation)
        except OperationError:
            continue
        try:
            got = interpret(context, s.strokes, s.camera, predictor, renderer)
            times.append(got.timings_ms["total"])
            ok = volume_iou(got.solid, truth) >= RECOVERY_IOU
        except InterpretError:
            ok = False
        hits[s.op_type].append(ok)
    return {"per_operator": {op.value: {"recovery_rate": float(np.mean(v)) if v else None,
                                        "recovery_n": len(v)} for op, v in hits.items()},
            "interpret_median": float(statistics.median(times)) if times else None}


def evaluate(data: Path, weights: Path | None, limit: int | None, recovery_limit: int) -> dict:
    torch.set_num_threads(2)
    predictor = load_predictor(weights)
    ds = Dataset(data)
    samples: list[Sample] = []
    for k in ds.shards:
        samples += ds.samples(k)
        if limit and len(samples) >= limit:
            break
    samples = samples[:limit] if limit else samples
    if not samples:
        raise ValueError(f"{data}: the data set holds no complete shard")
    out = network_metrics(predictor, samples)
    out["data"] = {"path": str(data), "seed": ds.manifest.get("seed"),
                   "noise": ds.manifest.get("noise")}
    if recovery_limit:
        rec = recovery(predictor, samples[:recovery_limit])
        for op, v in rec["per_operator"].items():
            out["per_operator"][op].update(v)
        out["latency_ms"]["interpret_median"] = rec["interpret_median"]
    return out


def report(result: dict, path: Path) -> None:
    """Confusion matrix and per-operator bars against the paper's Table 1."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    paper = {"extrude": (0.9178, 0.9804), "bevel": (0.9173, 0.9812), "addsub": (0.7826, 0.9354),
             "sweep": (0.7834, 0.9557)}
    cm = np.array(result["confusion_matrix"]["rows_true_cols_predicted"])
    names = result["confusion_matrix"]["classes"]
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.2))
    axes[0].imshow(cm, cmap="Blues")
    for i in range(4):
        for j in range(4):
            axes[0].text(j, i, str(cm[i, j]), ha="center", va="center")
    axes[0].set_xticks(range(4), names)
    axes[0].set_yticks(range(4), names)
    axes[0].set_xlabel("predicted")
    axes[0].set_ylabel("true")
    axes[0].set_title(f"classification accuracy {result['classification_accuracy']:.4f} "
                      f"(n={result['n']})")
    x = np.arange(4)
    ours_iou = [result["per_operator"][n]["face_iou"] or 0 for n in names]
    ours_acc = [result["per_operator"][n]["curve_accuracy"] or 0 for n in names]
    ax = axes[1]
    ax.bar(x - 0.3, ours_iou, 0.2, label="face IoU (ours)")
    ax.bar(x - 0.1, [paper[n][0] for n in names], 0.2, label="face IoU (paper)", alpha=0.5)
    ax.bar(x + 0.1, ours_acc, 0.2, label="curve acc. (ours)")
    ax.bar(x + 0.3, [paper[n][1] for n in names], 0.2, label="curve acc. (paper)", alpha=0.5)
    rec = [result["per_operator"][n].get("recovery_rate") for n in names]
    if any(r is not None for r in rec):
        ax.plot(x, [r or 0 for r in rec], "k*", ms=12, label="recovery rate (ours)")
    ax.set_xticks(x, names)
    ax.set_ylim(0, 1.05)
    ax.legend(fontsize=8, loc="lower left")
    ax.set_title("per operator")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("eval", help="evaluate the networks (and the whole pipeline) on a data set")
    p.add_argument("--data", type=Path, required=True, help="data set folder")
    p.add_argument("--weights", type=Path, help="weights file or run folder (default: shipped)")
    p.add_argument("--json", type=Path, required=True, help="write the figures here")
    p.add_argument("--report", type=Path, help="write a picture of the figures")
    p.add_argument("--limit", type=int, help="use at most this many samples")
    p.add_argument("--recovery", type=int, default=200,
                   help="samples for the end-to-end recovery rate (0 to skip; default 200)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    try:
        result = evaluate(args.data, args.weights, args.limit, args.recovery)
    except (FileNotFoundError, ValueError) as e:
        print(f"sketch2cad eval: error: {e}", file=sys.stderr)
        return 2
    args.json.write_text(json.dumps(result, indent=1))
    if args.report:
        report(result, args.report)
    print(json.dumps({k: result[k] for k in ("n", "classification_accuracy", "per_operator",
                                            "latency_ms")}, indent=1))
    return 0
