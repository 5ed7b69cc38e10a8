# SPDX-License-Identifier: LGPL-2.1-or-later
"""Making the workbench's dependency folder importable inside FreeCAD.

FreeCAD puts its system's site-packages (Debian: /usr/lib/python3/dist-packages) early
on sys.path, and Debian's pyparsing 3.0 and numpy 1.24 there break cadquery and pip's
scipy. So the dependency folder (see `dependencies`) goes to the front of sys.path before
anything imports numpy: Init.py calls `bootstrap()` when FreeCAD starts (GUI or
freecadcmd), before any workbench is activated or any document restored; the Install
button calls it again after installing. Nothing else on sys.path is moved. Other
workbenches then see the folder's numpy, scipy and matplotlib, consistent with each other.

Only the standard library (and FreeCAD) here, so it can run first.
"""

import os
import site
import sys

from . import dependencies

ROOT = dependencies.ROOT


def bootstrap() -> bool:
    """Put the repository root, then the dependency folder (with its .pth files), at the
    front of sys.path. Calling it again moves them to the front, never adds them twice.

    Returns:
        Whether the dependency folder exists (when not, the workbench offers to install).
    """
    deps = dependencies.folder()
    present = os.path.isdir(deps)
    before = set(sys.path)
    if present:
        site.addsitedir(deps)
    front = [ROOT] + ([deps] if present else [])
    front += [p for p in sys.path if p not in before and p not in front]
    sys.path[:] = front + [p for p in sys.path if p not in front]
    return present


def shadowed_modules() -> list[str]:
    """Modules already imported from outside the dependency folder that the folder also
    holds (numpy loaded by another workbench first, say): they need a restart of FreeCAD
    before the folder's copies are used."""
    deps = dependencies.folder()
    names = [n for n in ("numpy", "pyparsing", "scipy", "matplotlib") if n in sys.modules]
    return [
        n
        for n in names
        if os.path.isdir(os.path.join(deps, n))
        and not os.path.abspath(getattr(sys.modules[n], "__file__", "") or "").startswith(deps)
    ]
