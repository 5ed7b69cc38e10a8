# SPDX-License-Identifier: LGPL-2.1-or-later
"""End-to-end recovery with the structured head against the U-Net alone, on one data set.

    .bin/python scripts/recovery_with_head.py --data data/heldout-l1 --head runs/head \
        --limit 200 --json runs/recovery-l1.json

interpret() hands the sketch's strokes and face-ID map to a predictor that has `observe`
(inference/head/), so the whole pipeline (render, networks, fitting, B-rep) runs with
the head's F and C. Prints the recovery rates of training/recovery.py for each predictor
on the same samples; `--rows unet` or `--rows head` runs one (each takes minutes per 100
samples), and `--json` keeps them, merged into what the file already holds, so the two
rows can run apart and print together.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
import torch  # noqa: E402

from Sketch2CADWorkbench.inference.head.predictor import load_structured_predictor  # noqa: E402
from Sketch2CADWorkbench.inference.weights import HEAD_NAME, load_predictor  # noqa: E402
from training.recovery import recovery  # noqa: E402


def table(rows: dict, title: str) -> str:
    """The rows (name -> training.recovery result) as the printed table."""
    ops = list(next(iter(rows.values()))["per_operator"])
    lines = [
        f"{title}: recovery strict / with the flip (%)",
        "        " + "".join(f"{o:>16s}" for o in ops) + "   interpret ms",
    ]
    for name, r in rows.items():
        cells = "".join(
            f"{100 * v['recovery_rate']:7.1f} / {100 * v['recovery_rate_with_flip']:5.1f} "
            if v["recovery_n"]
            else f"{'-':>16s}"
            for v in r["per_operator"].values()
        )
        lines.append(f"{name:8s}{cells}  {r['interpret_median_ms']:.0f}")
        lines.append(
            f"        n: {[v['recovery_n'] for v in r['per_operator'].values()]}; "
            f"failures: {r['failure_reasons']}"
        )
    return "\n".join(lines)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--data", type=Path, required=True)
    p.add_argument("--head", type=Path, help="head file or its run folder (for the head row)")
    p.add_argument("--weights", type=Path, help="the U-Net (default: shipped)")
    p.add_argument("--limit", type=int, default=100)
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--rows", nargs="+", choices=("unet", "head"), default=["unet", "head"])
    p.add_argument("--json", type=Path, help="keep the rows here (merged with the file's)")
    args = p.parse_args()
    if "head" in args.rows and not args.head:
        p.error("the head row needs --head")
    torch.set_num_threads(args.threads)
    rows = json.loads(args.json.read_text()) if args.json and args.json.exists() else {}
    for name in args.rows:
        if name == "unet":
            predictor = load_predictor(args.weights, structured=False)
        else:
            head = args.head / HEAD_NAME if args.head.is_dir() else args.head
            predictor = load_structured_predictor(head, args.weights)
        rows[name] = recovery(args.data, predictor, args.limit)
        if args.json:
            args.json.parent.mkdir(parents=True, exist_ok=True)
            args.json.write_text(json.dumps(rows, indent=1))
    print(table(rows, f"{args.data}, first {args.limit} samples"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
