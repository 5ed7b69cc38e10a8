# SPDX-License-Identifier: LGPL-2.1-or-later
"""Build every bundled example protocol (examples/protocols) into STEP and PNG files.

`sketch2cad demo [--out out] [--examples DIR]`.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..brep.faces import OperationError
from ..brep.protocol import ProtocolError
from .build import build_files

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "protocols"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", type=Path, default=Path("out"), help="output folder (default: out)")
    p.add_argument("--examples", type=Path, default=EXAMPLES, help="folder of protocol files")


def run(args: argparse.Namespace) -> int:
    files = sorted(args.examples.glob("*.json"))
    if not files:
        print(f"sketch2cad demo: error: no protocol files in {args.examples}", file=sys.stderr)
        return 2
    args.out.mkdir(parents=True, exist_ok=True)
    failed = 0
    for f in files:
        try:
            build_files(f, args.out / f"{f.stem}.step", args.out / f"{f.stem}.png")
        except (ProtocolError, OperationError, OSError, ValueError) as e:
            print(f"sketch2cad demo: error: {e}", file=sys.stderr)
            failed += 1
    print(f"demo: {len(files) - failed} of {len(files)} protocols built into {args.out}/")
    return 1 if failed else 0
