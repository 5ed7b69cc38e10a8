# SPDX-License-Identifier: LGPL-2.1-or-later
"""Run by freecadcmd for `sketch2cad build P.json --fcstd OUT.FCStd` (cli/build.py): the
protocol SKETCH2CAD_PROTOCOL converted into PartDesign Bodies (convert.py), saved as
SKETCH2CAD_FCSTD. freecadcmd passes no arguments to a script, hence the environment.
Prints one line per step kept as a solid; exits 2 with the error when the protocol does
not load or build (freecadcmd would exit 0 on an uncaught exception).
"""

import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
sys.path.insert(0, ROOT)
for _name in [m for m in sys.modules if m.split(".")[0] == "Sketch2CADWorkbench"]:
    del sys.modules[_name]  # the workbench of FreeCAD's Mod folder may be another checkout


def main() -> int:
    from Sketch2CADWorkbench.freecad_layer import env

    env.bootstrap()
    import FreeCAD

    from Sketch2CADWorkbench.brep.faces import OperationError
    from Sketch2CADWorkbench.brep.protocol import ProtocolError, load
    from Sketch2CADWorkbench.freecad_layer.partdesign.convert import convert_protocol

    source, target = os.environ["SKETCH2CAD_PROTOCOL"], os.environ["SKETCH2CAD_FCSTD"]
    try:
        protocol = load(source)
        doc = FreeCAD.newDocument("Sketch2CAD")
        conversion = convert_protocol(doc, protocol, os.path.splitext(os.path.basename(source))[0])
    except (ProtocolError, OperationError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    doc.saveAs(target)
    native = sum(s.native for s in conversion.steps)
    print(
        f"  -> {len(conversion.bodies)} Body(ies), {native} of {len(conversion.steps)} steps native"
    )
    for step in conversion.steps:
        if not step.native:
            print(f"  step {step.step} ({step.label}) kept as a solid: {step.reason}")
    return 0


code = main()
sys.stdout.flush()
sys.stderr.flush()
os._exit(code)
