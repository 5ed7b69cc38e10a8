# SPDX-License-Identifier: LGPL-2.1-or-later
"""Making the project's virtual environment importable inside FreeCAD.

FreeCAD runs Debian's python3.11 with /usr/lib/python3/dist-packages early on sys.path;
Debian's pyparsing 3.0 and numpy 1.24 there break cadquery and the venv's scipy. So the
venv's site-packages go to the front of sys.path, before anything imports numpy: Init.py
calls `bootstrap()` when FreeCAD starts (GUI or freecadcmd), before any workbench is
activated or any document restored. Other workbenches then get the venv's numpy, scipy
and matplotlib too, which are consistent with each other (the venv holds all three).

This module imports nothing but the standard library, so it can run first.
"""
import os
import site
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SITE = os.path.join(ROOT, ".venv", "lib", "python3.11", "site-packages")


def bootstrap() -> None:
    """Put the repository root, then the venv's site-packages, at the front of sys.path.

    Calling it again is harmless: the entries are moved to the front, not added twice.

    Raises:
        ImportError: there is no virtual environment (the setup has not been run).
    """
    if not os.path.isdir(SITE):
        raise ImportError(f"Sketch2CAD: no virtual environment at {SITE}; run "
                          f"`bash scripts/setup.sh` in {ROOT} first")
    before = set(sys.path)
    site.addsitedir(SITE)  # also runs the venv's .pth files (the editable install's finder)
    front = [ROOT, SITE] + [p for p in sys.path if p not in before and p != SITE]
    sys.path[:] = front + [p for p in sys.path if p not in front]
