# SPDX-License-Identifier: LGPL-2.1-or-later
"""Replay PROTOCOL.json (schema in brep/protocol.py) and write the final solid.

`sketch2cad build PROTOCOL [--step OUT.step] [--png OUT.png] [--quiet]`.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..brep.exchange import export_step
from ..brep.faces import OperationError
from ..brep.operators import build
from ..brep.protocol import ProtocolError, load


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("protocol", type=Path, help="protocol JSON file")
    p.add_argument("--step", type=Path, help="write the solid as STEP AP214 (mm)")
    p.add_argument("--png", type=Path, help="write a shaded picture")
    p.add_argument("--quiet", action="store_true", help="do not print the protocol listing")


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


def run(args: argparse.Namespace) -> int:
    try:
        build_files(args.protocol, args.step, args.png, args.quiet)
    except (ProtocolError, OperationError, OSError) as e:
        print(f"sketch2cad build: error: {e}", file=sys.stderr)
        return 2
    return 0
