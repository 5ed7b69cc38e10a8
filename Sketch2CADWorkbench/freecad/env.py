# SPDX-License-Identifier: LGPL-2.1-or-later
"""Making the project's virtual environment importable inside FreeCAD.

FreeCAD runs Debian's python3.11 with /usr/lib/python3/dist-packages first on sys.path;
Debian's pyparsing and numpy there break cadquery and scipy. The venv's site-packages
(and the editable install's path to this repository) go to the front instead. This
must run before anything imports numpy; InitGui.py and the tests call it first.
"""
import os
import site
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SITE = os.path.join(ROOT, ".venv", "lib", "python3.11", "site-packages")


def bootstrap() -> None:
    """Put the venv's site-packages and the repository root at the front of sys.path."""
    if not os.path.isdir(SITE):
        raise ImportError(f"Sketch2CAD: no virtual environment at {SITE}; run `make test` or "
                          f"`bash scripts/setup.sh` in {ROOT} first")
    before = list(sys.path)
    site.addsitedir(SITE)  # also processes the .pth files of the editable install
    added = [p for p in sys.path if p not in before]
    rest = [p for p in sys.path if p not in added and p != ROOT]
    sys.path[:] = [ROOT] + added + rest
