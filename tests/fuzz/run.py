# SPDX-License-Identifier: LGPL-2.1-or-later
"""The full fuzzing campaigns, with their counts:

.bin/python tests/fuzz/run.py [--protocols 300] [--sessions 300] [--strokes 1000]
    [--kills 36] [--concurrent-seconds 20] [--geometry 100] [--seed 0]
"""

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import fuzzing


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--protocols", type=int, default=300)
    p.add_argument("--sessions", type=int, default=300)
    p.add_argument("--strokes", type=int, default=1000)
    p.add_argument("--kills", type=int, default=36)
    p.add_argument("--concurrent-seconds", type=float, default=20.0)
    p.add_argument("--geometry", type=int, default=100)
    p.add_argument("--seed", type=int, default=0)
    a = p.parse_args()
    t0 = time.perf_counter()
    tallies = [
        ("malformed protocols", fuzzing.malformed_protocols(a.protocols, a.seed)),
        ("malformed sessions", fuzzing.malformed_sessions(a.sessions, a.seed)),
        ("killed writers", fuzzing.killed_writers(a.kills, a.seed)),
        ("concurrent writers", fuzzing.concurrent_writers(a.concurrent_seconds)),
        ("output targets", fuzzing.output_targets(a.seed)),
        ("hostile geometry", fuzzing.hostile_geometry(a.geometry, a.seed)),
        ("random strokes", fuzzing.random_strokes(a.strokes, a.seed)),
    ]
    bad = 0
    for name, t in tallies:
        print(t.line(name))
        for c in t.crashes:
            print(f"    {c}")
        bad += sum(t.counts[k] for k in ("crash", "invalid", "changed", "broken", "leftover"))
    print(f"fuzz: {bad} failures in {time.perf_counter() - t0:.0f} s")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
