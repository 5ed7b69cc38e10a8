# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad`: the command line over the core (no FreeCAD needed), the top layer.

One module per command in this package, named as the command (`option-scan` is
option_scan.py). Each has a docstring (the command's description), `add_arguments(parser)`
and `run(args) -> int` (the exit code). Only the module of the command asked for is
imported: the others would load torch, cadquery and VTK for nothing (seconds).
"""

from __future__ import annotations

import argparse
import importlib
import sys

# command -> one-line help
COMMANDS = {
    "build": "replay a protocol into a solid; write STEP and a picture",
    "export-script": "write a protocol as a CadQuery or build123d script that rebuilds the model",
    "demo": "build every bundled example protocol into STEP + PNG",
    "interpret": "interpret a sketch session into a protocol and a solid",
    "datagen": "generate synthetic training/evaluation samples",
    "train": "train the networks on a generated data set",
    "eval": "evaluate the networks on a held-out data set",
    "train-head": "train and score the structured heads on the frozen networks",
    "diagnose": "tally the fitting stage's misses on a data set, by cause",
    "option-scan": "how often the other Boolean is named, and the wrong options it covers",
    "head-recovery": "end-to-end recovery with the structured head beside the U-Net alone",
    "model-card": "write the shipped weights' model card from a run and its evaluations",
    "oracle": "how close a sketch session's strokes let a reading end",
    "extrusion-bound": "the most any reading of a set's extrusions (or shells) can recover",
}


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    parser = argparse.ArgumentParser(
        prog="sketch2cad",
        description="Sketch2CAD: sequential CAD modeling by sketching in context.",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    wanted = next((a for a in argv if not a.startswith("-")), None)
    for name, text in COMMANDS.items():
        if name != wanted:  # listed in the help, parsed only when asked for
            sub.add_parser(name, help=text, add_help=False)
            continue
        module = importlib.import_module(f"{__name__}.{name.replace('-', '_')}")
        p = sub.add_parser(name, help=text, description=module.__doc__.split("\n\n")[0])
        module.add_arguments(p)
        p.set_defaults(func=module.run)
    args = parser.parse_args(argv)
    return int(args.func(args) or 0)
