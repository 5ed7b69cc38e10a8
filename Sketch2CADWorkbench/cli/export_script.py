# SPDX-License-Identifier: LGPL-2.1-or-later
"""Write a protocol as a script that rebuilds the model with CadQuery's public API.

`sketch2cad export-script PROTOCOL --cadquery OUT.py`: one block per step with the
step's parameters as named variables; the script needs only cadquery to run
(brep/script.py).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..brep.faces import OperationError
from ..brep.features import plan_protocol
from ..brep.files import check_outputs, write_atomically
from ..brep.protocol import ProtocolError, load
from ..brep.script import cadquery_script


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("protocol", type=Path, help="protocol JSON file")
    p.add_argument(
        "--cadquery", type=Path, required=True, help="write the CadQuery script here (.py)"
    )


def run(args: argparse.Namespace) -> int:
    try:
        check_outputs({"PROTOCOL": args.protocol}, {"--cadquery": args.cadquery})
        protocol = load(args.protocol)
        text = cadquery_script(plan_protocol(protocol), args.protocol.stem)
        args.cadquery.parent.mkdir(parents=True, exist_ok=True)
        write_atomically(args.cadquery, text)
    except (ProtocolError, OperationError, OSError, ValueError) as e:
        print(f"sketch2cad export-script: error: {e}", file=sys.stderr)
        return 2
    print(f"{args.protocol}: {len(protocol.operations) + 1} steps -> {args.cadquery}")
    return 0
