# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad build` (a protocol to STEP and a picture) and `sketch2cad demo`."""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .exchange import export_step
from .faces import OperationError
from .operators import build
from .protocol import ProtocolError, load

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "protocols"


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("build",
                       description="Replay PROTOCOL.json (see brep/protocol.py for the "
                                   "schema) and write the final solid.")
    p.add_argument("protocol", type=Path, help="protocol JSON file")
    p.add_argument("--step", type=Path, help="write the solid as STEP AP214 (mm)")
    p.add_argument("--png", type=Path, help="write a shaded picture")
    p.add_argument("--quiet", action="store_true", help="do not print the protocol listing")
    p.set_defaults(func=run_build)

    d = sub.add_parser("demo")
    d.add_argument("--out", type=Path, default=Path("out"), help="output folder (default: out)")
    d.add_argument("--examples", type=Path, default=EXAMPLES, help="folder of protocol files")
    d.set_defaults(func=run_demo)


def build_files(protocol_path: Path, step: Path | None, png: Path | None, quiet: bool = False):
    """Replay one protocol file and write its outputs; returns the final solid."""
    protocol = load(protocol_path)
    if not quiet:
        print(f"{protocol_path}:\n{protocol.listing()}")
    solid = build(protocol)
    if step:
        export_step(solid, step)
    if png:
        from ..render.picture import shaded_picture  # VTK only when a picture is asked for
        shaded_picture(solid, path=png)
    if not quiet:
        bb = solid.BoundingBox()
        print(f"  -> volume {solid.Volume():.2f} mm^3, size {bb.xlen:.1f} x {bb.ylen:.1f} x "
              f"{bb.zlen:.1f} mm" + (f", {step}" if step else "") + (f", {png}" if png else ""))
    return solid


def run_build(args: argparse.Namespace) -> int:
    try:
        build_files(args.protocol, args.step, args.png, args.quiet)
    except (ProtocolError, OperationError, OSError) as e:
        print(f"sketch2cad build: error: {e}", file=sys.stderr)
        return 2
    return 0


def run_demo(args: argparse.Namespace) -> int:
    files = sorted(args.examples.glob("*.json"))
    if not files:
        print(f"sketch2cad demo: error: no protocol files in {args.examples}", file=sys.stderr)
        return 2
    args.out.mkdir(parents=True, exist_ok=True)
    failed = 0
    for f in files:
        try:
            build_files(f, args.out / f"{f.stem}.step", args.out / f"{f.stem}.png")
        except (ProtocolError, OperationError, OSError) as e:
            print(f"sketch2cad demo: error: {e}", file=sys.stderr)
            failed += 1
    print(f"demo: {len(files) - failed} of {len(files)} protocols built into {args.out}/")
    return 1 if failed else 0
