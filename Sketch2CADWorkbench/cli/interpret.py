# SPDX-License-Identifier: LGPL-2.1-or-later
"""Run every step of a sketch session (see inference/session.py) through the networks and
fitting, into a protocol and a solid.

`sketch2cad interpret SESSION.json [--protocol P.json] [--step S.step] [--png S.png]`;
`--compare P.json` prints each step's volume IoU with the protocol the sketches mean, and
with `--each-step` reads every step on that protocol's model, one step's miss not carried
into the next, and says where the session would end with that step so read and every
other step exact.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path

from tqdm import tqdm

from ..brep.compare import volume_iou
from ..brep.files import check_outputs
from ..brep.operators import apply_what_builds, make_box, replay
from ..brep.protocol import Protocol, ProtocolError, describe, load
from ..inference.context import InterpretError
from ..inference.fitting.regularize import SNAP_PX
from ..inference.interpret import interpret
from ..inference.session import load_session
from .build import output_file, replay_progress, write_outputs


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("session", type=Path, help="session JSON file")
    p.add_argument("--protocol", type=output_file, help="write the interpreted protocol (JSON)")
    p.add_argument("--step", type=output_file, help="write the final solid as STEP AP214")
    p.add_argument("--png", type=output_file, help="write a picture of the final solid (PNG)")
    p.add_argument("--weights", type=Path, help="network weights (default: shipped)")
    p.add_argument(
        "--compare",
        type=Path,
        metavar="PROTOCOL",
        help="the model the sketches mean (a protocol with one operation per "
        "step): print each step's volume IoU with it",
    )
    p.add_argument(
        "--each-step",
        action="store_true",
        help="with --compare, read every step on the compared protocol's model "
        "before it, not on the model the earlier readings built, and print "
        "that step's volume IoU alone (where a session loses, step by step), "
        "and the final one with every other step exact",
    )
    p.add_argument(
        "--regularize",
        choices=("session", "on", "off"),
        default="session",
        help="snapping and rectification: as each step's choices say (default), "
        "or on or off for every step",
    )
    p.add_argument(
        "--snap-step",
        type=float,
        metavar="MM",
        help="with regularization, round lengths to multiples of this step in "
        "every step (default: each step's own, else 0: no grid)",
    )
    p.add_argument(
        "--snap-px",
        type=float,
        metavar="PX",
        help="with regularization, snap to targets within this many pixels of "
        "the view the strokes were drawn in, in every step (default: each "
        f"step's own, else {SNAP_PX})",
    )
    p.add_argument(
        "--keep-going",
        action="store_true",
        help="skip a step that cannot be interpreted, or whose reading is doubtful, "
        "instead of stopping (the skipped steps are listed; the exit code is then 0)",
    )
    p.add_argument(
        "--accept-doubtful",
        action="store_true",
        help="add a doubtful reading (the strokes do not look much like it: a "
        "scribble, or a sketch the networks misread) with its warning, instead of "
        "stopping, or skipping it with --keep-going",
    )


def run(args: argparse.Namespace) -> int:
    from ..inference.weights import load_predictor
    from ..render.maps import MapRenderer

    try:
        check_outputs(
            {"SESSION": args.session, "--compare": args.compare, "--weights": args.weights},
            {"--protocol": args.protocol, "--step": args.step, "--png": args.png},
        )
    except ValueError as e:
        print(f"sketch2cad interpret: error: {e}", file=sys.stderr)
        return 2
    if args.each_step and (not args.compare or args.protocol or args.step or args.png):
        print(
            "sketch2cad interpret: error: --each-step needs --compare, and reads each step "
            "on that protocol's model, so it writes no --protocol, --step or --png",
            file=sys.stderr,
        )
        return 2
    try:
        session = load_session(args.session)
        if not session.steps:
            raise ValueError(
                f"{args.session}: the session has no sketched steps (steps: []), so there "
                "is nothing to interpret; nothing was written"
            )
        meant, reference = (
            _reference(args.compare, len(session.steps)) if args.compare else (None, None)
        )
        predictor = load_predictor(args.weights)
    except (ProtocolError, FileNotFoundError, ValueError) as e:
        print(f"sketch2cad interpret: error: {e}", file=sys.stderr)
        return 2
    renderer = MapRenderer()
    protocol, solid = Protocol(session.base), make_box(session.base)
    print(f"{args.session}: box {session.base.size} mm, {len(session.steps)} sketched steps")
    failed = 0
    with replay_progress(len(session.steps), f"interpret {args.session.name}") as bar:
        for i, step in enumerate(session.steps, 1):
            choices = step.choices  # with the snaps the designer undid (skip_snaps)
            if args.snap_step is not None:
                choices = replace(choices, snap_step=args.snap_step)
            if args.snap_px is not None:
                choices = replace(choices, snap_px=args.snap_px)
            if args.regularize != "session":
                choices = replace(choices, regularize=args.regularize == "on")
            if args.each_step:  # the step alone, on the model the designer drew it over
                solid = reference[i - 1]
            try:
                got = interpret(solid, step.strokes, step.camera, predictor, renderer, choices)
            except InterpretError as e:
                got = None
                failed += 1
                tqdm.write(f"step {i}: not interpreted: {e}", file=sys.stderr)
                if not args.keep_going:
                    return 2
            if got is not None and got.doubtful and not args.accept_doubtful:
                failed += 1
                tqdm.write(f"step {i}: doubtful, not added: {got.doubt()}", file=sys.stderr)
                got = None
                if not args.keep_going:
                    tqdm.write(
                        "sketch2cad interpret: stopped, nothing written; --accept-doubtful adds "
                        "such a reading, --keep-going skips it",
                        file=sys.stderr,
                    )
                    return 2
            if got is not None:
                for op in got.operations:
                    protocol = protocol.append(op)
                    tqdm.write(f"step {i}: {describe(op)}")
                for snap in got.snaps:
                    tqdm.write(f"         (snapped: {snap.describe()})")
                if got.unsnapped:
                    tqdm.write(f"         (not snapped: {got.unsnapped})")
                tqdm.write(
                    f"         ({got.op_type.value} {got.probabilities[got.op_type.value]:.0%}, "
                    f"{got.timings_ms['total']:.0f} ms)"
                )
                if got.doubtful:
                    tqdm.write(f"         (warning: {got.doubt()})")
                if got.other_option is not None:
                    tqdm.write(
                        f"         (the strokes read just as well as {got.other_option.value}: "
                        f"set this step's choices.option to have it)"
                    )
                solid = got.solid
            if reference:
                alone = " (this step alone)" if args.each_step else ""
                line = (
                    f"         volume IoU with {args.compare.name} after step {i}{alone}: "
                    f"{volume_iou(solid, reference[i]):.3f}"
                )
                if args.each_step and got is not None:
                    ends = apply_what_builds(solid, list(meant.operations[i:]))
                    line += (
                        f"; the session so, every other step exact: "
                        f"{volume_iou(ends, reference[-1]):.3f}"
                    )
                tqdm.write(line)
            bar.update(1)

    print(
        f"interpret: {len(session.steps) - failed} of {len(session.steps)} steps interpreted; "
        f"volume {solid.Volume():.1f} mm^3"
    )
    try:
        write_outputs(solid, protocol, args.step, args.png, args.protocol)
    except OSError as e:
        print(
            f"sketch2cad interpret: error: {e}; no output was written or replaced", file=sys.stderr
        )
        return 2
    return 0


def _reference(path: Path, steps: int) -> tuple[Protocol, list]:
    """The reference protocol and its solids (base, then after each operation), one
    operation per step."""
    meant = load(path)
    if len(meant.operations) != steps:
        raise ProtocolError(
            f"{path}: {len(meant.operations)} operations for {steps} sketched "
            "steps; --compare needs one operation per step"
        )
    with replay_progress(len(meant.operations), f"replay {path.name}") as bar:
        return meant, replay(meant, on_step=lambda i: bar.update(1))
