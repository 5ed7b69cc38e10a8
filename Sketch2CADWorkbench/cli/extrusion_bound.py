# SPDX-License-Identifier: LGPL-2.1-or-later
"""The most any reading of an extrusion's strokes can recover (training/extrusion_bound.py).

`sketch2cad extrusion-bound data/heldout-l1c [MORE ...] [--limit N] [--json OUT.json]`:
for each set's extrusions on planar faces, an oracle that knows f and which tip was drawn
from which corner estimates d by least squares (the generator's end-point noise is
Gaussian); with the generator's prior on d, the decision most likely to pass the
recovery test (volume IoU >= 0.95) and its posterior probability of passing. Prints the
oracle's rate, the best decision's rate and the expected rate, which bounds what any
reading of these strokes can expect (compare `sketch2cad eval --recovery`'s extrude
rate). Sets of one noise level pool into one line. With `--shells` the same for the
set's shells' wall thickness t, read from the tips drawn at the rim's corners
(training/shell_bound.py).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from training import extrusion_bound, shell_bound


def pooled(rows: list[dict]) -> dict:
    """Sets' figures weighted by their sample counts."""
    n = sum(r["n"] for r in rows)
    return {
        "n": n,
        **{
            k: sum(r[k] * r["n"] for r in rows) / n
            for k in ("oracle_ml_rate", "best_decision_rate", "expected_bound", "fitting_rate")
            if all(r.get(k) is not None for r in rows)
        },
    }


def line(name: str, r: dict, what: str) -> str:
    fitting = r.get("fitting_rate")
    return (
        f"{name}: {r['n']} {what}; oracle least squares {100 * r['oracle_ml_rate']:.1f}%, "
        f"best decision {100 * r['best_decision_rate']:.1f}%, expected (the bound) "
        f"{100 * r['expected_bound']:.1f}%"
        + ("" if fitting is None else f"; the fitting, told f: {100 * fitting:.1f}%")
    )


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("data", nargs="+", help="generated sets (sketch2cad datagen --out)")
    p.add_argument("--limit", type=int, default=None, help="samples read per set")
    p.add_argument("--json", type=Path, default=None, help="write the figures here")
    p.add_argument(
        "--shells",
        action="store_true",
        help="bound the shells' wall thickness (rims of lines only), not the extrusions",
    )


def run(args: argparse.Namespace) -> int:
    missing = [d for d in args.data if not Path(d).is_dir()]
    if missing:
        print(
            f"sketch2cad extrusion-bound: error: {missing[0]}: no such generated set",
            file=sys.stderr,
        )
        return 2
    module, what, none = (
        (shell_bound, "shells", "no shell with a rim of lines")
        if args.shells
        else (extrusion_bound, "extrusions", "no extrusion on a planar face")
    )
    rows = {}
    for d in args.data:
        rows[d] = module.bound_of_set(d, args.limit)
        if rows[d]["n"] == 0:
            print(f"{d}: {none}")
            continue
        print(line(d, rows[d], what), flush=True)
    counted = [r for r in rows.values() if r["n"]]
    if len(counted) > 1:
        rows["pooled"] = pooled(counted)
        print(line("pooled", rows["pooled"], what))
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))
    return 0
