# SPDX-License-Identifier: LGPL-2.1-or-later
"""Replay PROTOCOL.json (schema in brep/protocol.py) and write the final solid.

`sketch2cad build PROTOCOL [--step OUT.step] [--png OUT.png] [--quiet]`.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from tqdm import tqdm

from ..brep.exchange import export_step
from ..brep.faces import OperationError
from ..brep.files import atomic_outputs, check_outputs
from ..brep.operators import build
from ..brep.protocol import Protocol, ProtocolError, load

PROGRESS_FROM = 20  # operations: a protocol this long shows a progress bar while it builds


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("protocol", type=Path, help="protocol JSON file")
    p.add_argument("--step", type=Path, help="write the solid as STEP AP214 (mm)")
    p.add_argument("--png", type=Path, help="write a shaded picture")
    p.add_argument("--quiet", action="store_true", help="do not print the protocol listing")


def write_outputs(
    solid,
    protocol: Protocol | None,
    step: Path | None,
    png: Path | None,
    protocol_path: Path | None = None,
) -> None:
    """Write the asked-for outputs of a command all or none: each to a temporary beside it,
    moved into place only when every one was written (brep/files.py).

    Raises:
        OSError: an output could not be written; no file was replaced.
    """
    writers = []
    if protocol_path:
        writers.append((protocol_path, lambda tmp: protocol.save(tmp)))
    if step:
        writers.append((step, lambda tmp: export_step(solid, tmp)))
    if png:
        from ..render.picture import shaded_picture  # VTK only when a picture is asked for

        writers.append((png, lambda tmp: shaded_picture(solid, path=tmp)))
    for path, _ in writers:
        path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_outputs([path for path, _ in writers]) as tmps:
        for tmp, (_, write) in zip(tmps, writers, strict=True):
            write(tmp)


def build_files(protocol_path: Path, step: Path | None, png: Path | None, quiet: bool = False):
    """Replay one protocol file and write its outputs (all or none); returns the solid.

    Raises:
        ValueError: an output is the protocol file or the other output.
    """
    check_outputs({"PROTOCOL": protocol_path}, {"--step": step, "--png": png})
    protocol = load(protocol_path)
    if not quiet:
        print(f"{protocol_path}:\n{protocol.listing()}")
    steps = len(protocol.operations)
    with tqdm(
        total=steps,
        desc=f"build {protocol_path.name}",
        unit="step",
        leave=False,
        disable=steps < PROGRESS_FROM,
    ) as bar:
        solid = build(protocol, on_step=lambda i: bar.update(1))
    write_outputs(solid, protocol, step, png)
    if not quiet:
        bb = solid.BoundingBox()
        print(
            f"  -> volume {solid.Volume():.2f} mm^3, size {bb.xlen:.1f} x {bb.ylen:.1f} x "
            f"{bb.zlen:.1f} mm" + (f", {step}" if step else "") + (f", {png}" if png else "")
        )
    return solid


def run(args: argparse.Namespace) -> int:
    try:
        build_files(args.protocol, args.step, args.png, args.quiet)
    except (ProtocolError, OperationError, OSError, ValueError) as e:
        print(f"sketch2cad build: error: {e}", file=sys.stderr)
        return 2
    return 0
