# SPDX-License-Identifier: LGPL-2.1-or-later
"""Write a protocol as a script that rebuilds the model with CadQuery's or build123d's
public API.

`sketch2cad export-script PROTOCOL --cadquery OUT.py` (or `--build123d OUT.py`, or
both): one block per step with the step's parameters as named variables; the script
needs only its library to run (brep/script.py).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..brep.faces import OperationError
from ..brep.features import plan_protocol
from ..brep.files import atomic_outputs, check_outputs
from ..brep.protocol import ProtocolError, load
from ..brep.script import LIBRARIES, protocol_script


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("protocol", type=Path, help="protocol JSON file")
    for library in LIBRARIES:
        p.add_argument(
            f"--{library}", type=Path, metavar="OUT.py", help=f"write the {library} script here"
        )


def run(args: argparse.Namespace) -> int:
    wanted = {name: getattr(args, name) for name in LIBRARIES if getattr(args, name) is not None}
    if not wanted:
        options = " or ".join(f"--{name}" for name in LIBRARIES)
        print(
            f"sketch2cad export-script: error: give {options} (the script to write)",
            file=sys.stderr,
        )
        return 2
    try:
        check_outputs({"PROTOCOL": args.protocol}, {f"--{n}": p for n, p in wanted.items()})
        protocol = load(args.protocol)
        plan = plan_protocol(protocol)
        for path in wanted.values():
            path.parent.mkdir(parents=True, exist_ok=True)
        with atomic_outputs(list(wanted.values())) as tmps:  # all or none
            for tmp, library in zip(tmps, wanted, strict=True):
                tmp.write_text(protocol_script(plan, args.protocol.stem, library))
    except (ProtocolError, OperationError, OSError, ValueError) as e:
        print(f"sketch2cad export-script: error: {e}", file=sys.stderr)
        return 2
    written = ", ".join(map(str, wanted.values()))
    print(f"{args.protocol}: {len(protocol.operations) + 1} steps -> {written}")
    return 0
