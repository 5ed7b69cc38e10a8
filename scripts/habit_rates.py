# SPDX-License-Identifier: LGPL-2.1-or-later
"""What each of people's drawing habits costs the shipped pipeline, beside the generator's
hand: recovery on sets that share their operations and views.

    .bin/python scripts/habit_rates.py [--count 60] [--levels 1 3] [--json docs/eval/habits.json]

For each noise level, one set per hand of `datagen.hand.HANDS` (the generator's, people's
with every habit, people's with one habit alone) is made with `sketch2cad datagen` under
data/ with the same seed, then read by `sketch2cad eval --recovery` (shipped networks,
regularization off; recovered: volume IoU >= 0.95, strict and counting the named flip of
the Boolean). Sets and evaluations already made are reused, so a rerun resumes. Prints
a table and writes the figures with the commands that made them.
"""

import argparse
import json
import subprocess
import sys
from pathlib import Path

from datagen.hand import HANDS
from Sketch2CADWorkbench.brep.files import write_atomically

SEED = 41100  # + the noise level: the sets of one level share their operations
ROOT = Path(__file__).resolve().parent.parent


def _run(args: list[str]) -> None:
    subprocess.run([str(ROOT / ".bin" / "sketch2cad"), *args], check=True, cwd=ROOT)


def measure(level: int, hand: str, count: int, folder: Path) -> dict:
    """Make (or reuse) one set and read it; its recovery per operator and in all."""
    data = Path("data") / f"l{level}-{hand}"
    out = folder / f"{data.name}.json"
    made_by = (
        f"sketch2cad datagen --out {data} --count {count} --seed {SEED + level} "
        f"--noise-level {level} --hand {hand}"
    )
    command = f"sketch2cad eval --data {data} --json J --recovery {count} --latency-runs 1"
    if not out.exists():
        _run(made_by.split()[1:])
        _run([*command.replace("J", str(out)).split()[1:]])
    per = json.loads(out.read_text())["per_operator"]
    ops = {
        op: {
            "n": d["recovery_n"],
            "recovered": round(d["recovery_rate"] * d["recovery_n"]),
            "recovered_with_flip": round(d["recovery_rate_with_flip"] * d["recovery_n"]),
        }
        for op, d in per.items()
        if d.get("recovery_n")
    }
    n = sum(d["n"] for d in ops.values())
    return {
        "made_by": made_by,
        "commands": [command],
        "noise_level": level,
        "hand": hand,
        "n": n,
        "recovery_rate": round(sum(d["recovered"] for d in ops.values()) / n, 3),
        "recovery_rate_with_flip": round(
            sum(d["recovered_with_flip"] for d in ops.values()) / n, 3
        ),
        "per_operator": ops,
    }


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--count", type=int, default=60, help="samples per set (default 60)")
    p.add_argument("--levels", type=int, nargs="+", default=[1, 3], choices=(1, 2, 3))
    p.add_argument("--json", type=Path, default=ROOT / "docs" / "eval" / "habits.json")
    p.add_argument(
        "--evals", type=Path, default=ROOT / "runs" / "habits", help="each set's eval JSON"
    )
    a = p.parse_args()
    a.evals.mkdir(parents=True, exist_ok=True)
    sets = {}
    for level in a.levels:
        for hand in HANDS:
            r = sets[f"l{level}-{hand}"] = measure(level, hand, a.count, a.evals)
            print(
                f"level {level} {hand:<16} {100 * r['recovery_rate']:5.1f}% / "
                f"{100 * r['recovery_rate_with_flip']:5.1f}%  "
                + "  ".join(
                    f"{op} {d['recovered']}/{d['recovered_with_flip']} of {d['n']}"
                    for op, d in r["per_operator"].items()
                ),
                flush=True,
            )
    about = (
        f"recovery of the shipped pipeline (regularization off; recovered: volume IoU >= "
        f"0.95 with the truth, strict and counting the named flip of the Boolean) on fresh "
        f"sets of {a.count} samples drawn by the generator's hand, by people's hand with "
        "every habit, and by people's hand with one habit alone (the others off: whole "
        "curves, one stroke each, every line, no bow); the sets of one level share their "
        "operations and views (`.bin/python scripts/habit_rates.py`)"
    )
    write_atomically(a.json, json.dumps({"about": about, "sets": sets}, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
