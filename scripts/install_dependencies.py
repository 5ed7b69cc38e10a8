# SPDX-License-Identifier: LGPL-2.1-or-later
"""Run by scripts/setup.sh in freecadcmd: installs the workbench's dependencies exactly as
its Install button does (Sketch2CADWorkbench/freecad_layer/dependencies.py), into this
FreeCAD's own folder for them, with this FreeCAD's Python. Quick when nothing changed.

Environment: SKETCH2CAD_EXTRAS (pyproject's optional groups, comma-separated, e.g.
"test"), and the settings `dependencies.setting` reads (SKETCH2CAD_TORCH_REQUIREMENT,
SKETCH2CAD_TORCH_INDEX, SKETCH2CAD_DEPENDENCY_FOLDER, SKETCH2CAD_PYTHON).
Its last line is "python=<interpreter> folder=<dependency folder>" for setup.sh.
"""

import os
import sys

from Sketch2CADWorkbench.freecad_layer import dependencies, env


def main() -> int:
    extras = tuple(e for e in os.environ.get("SKETCH2CAD_EXTRAS", "").split(",") if e)
    try:
        plan = dependencies.user_plan(extras)
        if dependencies.is_installed(plan):
            print(f"install_dependencies: {plan.target} is up to date")
        else:
            print(
                f"install_dependencies: installing into {plan.target} with {plan.python}"
                + (f" (from the system: {', '.join(plan.skipped)})" if plan.skipped else "")
            )
            dependencies.install(plan, on_line=lambda line: print("    " + line, flush=True))
    except dependencies.InstallError as e:
        print(f"install_dependencies: {e}", file=sys.stderr)
        return 1
    env.bootstrap()
    print(f"python={plan.python} folder={plan.target}", flush=True)
    return 0


sys.exit(main())
