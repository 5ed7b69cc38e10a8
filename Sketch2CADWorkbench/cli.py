# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad`: the command line over the core (no FreeCAD needed).

Each subcommand lives in its own module, which exposes `register(subparsers)`; the
module adds its parser and sets `func` to the handler, which returns an exit code.
Only the module of the command asked for is imported: the others would load torch,
cadquery and VTK for nothing (seconds of start-up).
"""
from __future__ import annotations

import argparse
import importlib
import sys

# module -> {command: one-line help}
COMMANDS = {
    "Sketch2CADWorkbench.brep.commands": {
        "build": "replay a protocol into a solid; write STEP and a picture",
        "demo": "build every bundled example protocol into STEP + PNG"},
    "datagen.command": {
        "datagen": "generate synthetic training/evaluation samples"},
    "Sketch2CADWorkbench.inference.train": {
        "train": "train the networks on a generated data set"},
    "Sketch2CADWorkbench.inference.evaluate": {
        "eval": "evaluate the networks on a held-out data set"},
    "Sketch2CADWorkbench.inference.interpret_command": {
        "interpret": "interpret a sketch session into a protocol and a solid"},
}


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    parser = argparse.ArgumentParser(
        prog="sketch2cad",
        description="Sketch2CAD: sequential CAD modeling by sketching in context.")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    wanted = next((a for a in argv if not a.startswith("-")), None)
    for module, commands in COMMANDS.items():
        if wanted in commands:
            importlib.import_module(module).register(sub)
        else:  # listed in the help, parsed only when asked for
            for name, text in commands.items():
                sub.add_parser(name, help=text, add_help=False)
    args = parser.parse_args(argv)
    return int(args.func(args) or 0)


if __name__ == "__main__":
    sys.exit(main())
