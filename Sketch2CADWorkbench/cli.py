# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad`: the command line over the core (no FreeCAD needed).

Each subcommand lives in its own module, which exposes `register(subparsers)`; the
module adds its parser and sets `func` to the handler, which returns an exit code.
"""
from __future__ import annotations

import argparse
import importlib
import sys

COMMAND_MODULES = [
    "Sketch2CADWorkbench.brep.commands",
    "Sketch2CADWorkbench.datagen.command",
    "Sketch2CADWorkbench.inference.train",
    "Sketch2CADWorkbench.inference.evaluate",
    "Sketch2CADWorkbench.inference.interpret_command",
]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="sketch2cad",
        description="Sketch2CAD: sequential CAD modeling by sketching in context.")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name in COMMAND_MODULES:
        importlib.import_module(name).register(sub)
    args = parser.parse_args(argv)
    return int(args.func(args) or 0)


if __name__ == "__main__":
    sys.exit(main())
