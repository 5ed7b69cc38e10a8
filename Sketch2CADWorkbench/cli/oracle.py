# SPDX-License-Identifier: LGPL-2.1-or-later
"""How close a sketch session's strokes let a reading end (training/session_oracle.py).

`sketch2cad oracle SESSION PROTOCOL` (or `--examples`, the seven example sessions;
`--json OUT.json` keeps the figures): each step read by an oracle that knows the
protocol's structure and which stroke draws which curve, its numbers by least squares on
the strokes; one line per step (volume IoU alone on the true model before it, as read and
as the step's choices snap it), then the final IoU of the oracle's protocol. Beside
`sketch2cad interpret SESSION --compare PROTOCOL [--each-step]`, it tells a reading's
shortfall from what the strokes hold.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
from pathlib import Path

from tqdm import tqdm

from training.session_oracle import session_oracle

from ..brep.protocol import ProtocolError, describe, load
from ..inference.session import load_session

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ("camera", "hammer", "mixer", "bolt", "lamp", "pipe", "enclosure", "knob")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("files", nargs="*", metavar="SESSION PROTOCOL")
    p.add_argument(
        "--examples", action="store_true", help="the seven example sessions with their protocols"
    )
    p.add_argument("--json", type=Path, help="write the figures here")


def _pairs(args: argparse.Namespace) -> list[tuple[Path, Path]] | None:
    """(session, protocol) pairs to read, or None when the arguments name none."""
    if args.examples:
        return [
            (
                ROOT / "examples" / "sessions" / f"{n}.json",
                ROOT / "examples" / "protocols" / f"{n}.json",
            )
            for n in EXAMPLES
        ]
    if len(args.files) != 2:
        return None
    return [(Path(args.files[0]), Path(args.files[1]))]


def _error(text: str) -> int:
    print(f"sketch2cad oracle: error: {text}", file=sys.stderr)
    return 2


def run(args: argparse.Namespace) -> int:
    pairs = _pairs(args)
    if pairs is None:
        return _error("give a session and its protocol, or --examples")
    report = {}
    for session_path, protocol_path in pairs:
        try:
            session, protocol = load_session(session_path), load(protocol_path)
        except (OSError, ProtocolError) as e:
            return _error(str(e))
        name = session_path.stem
        with tqdm(total=len(session.steps), desc=name, leave=False) as bar:
            try:
                got = session_oracle(session, protocol, on_step=lambda _: bar.update())
            except ValueError as e:
                return _error(f"{session_path}: {e}")
        weakest, bound = got.weakest
        print(
            f"{name}: oracle's final volume IoU {got.final_iou:.3f}, "
            f"snapped as the steps choose {got.regularized_iou:.3f}; with every other "
            f"step exact, step {weakest} alone ends it at {bound:.3f} at best"
        )
        for k, s in enumerate(got.steps, 1):
            print(
                f"  step {k}: alone {s.iou:.3f}, snapped {s.snapped_iou:.3f} (the session "
                f"{s.session_iou:.3f} / {s.snapped_session_iou:.3f}); ends and loops miss "
                f"it by {s.rms_px:.2f} px rms "
                f"(the truth by {s.truth_rms_px:.2f}), {s.strokes} strokes: "
                f"{describe(s.snapped)}"
            )
        report[name] = {
            "final_iou": got.final_iou,
            "regularized_iou": got.regularized_iou,
            "weakest_step": weakest,
            "weakest_session_iou": bound,
            "steps": [
                {k: v for k, v in dataclasses.asdict(s).items() if k not in ("reading", "snapped")}
                for s in got.steps
            ],
        }
    if args.json:
        args.json.write_text(json.dumps(report, indent=1) + "\n")
    return 0
