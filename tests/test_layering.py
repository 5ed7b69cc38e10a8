# SPDX-License-Identifier: LGPL-2.1-or-later
"""The core runs without FreeCAD: only the FreeCAD layer imports it."""
import ast
import subprocess
import sys
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "Sketch2CADWorkbench"
FREECAD_LAYER = {"freecad_layer", "commands"}
FREECAD_FILES = {"InitGui.py", "Init.py"}


def _imports(path: Path) -> set[str]:
    names = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            names |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module.split(".")[0])
    return names


def test_only_the_freecad_layer_imports_freecad():
    offenders = []
    for f in PACKAGE.rglob("*.py"):
        rel = f.relative_to(PACKAGE)
        if rel.parts[0] in FREECAD_LAYER or rel.name in FREECAD_FILES:
            continue
        if _imports(f) & {"FreeCAD", "FreeCADGui", "Part", "pivy"}:
            offenders.append(str(rel))
    assert offenders == []


def test_core_imports_and_builds_without_freecad_on_the_path():
    code = ("import sys; import Sketch2CADWorkbench.brep.operators, Sketch2CADWorkbench.cli; "
            "assert 'FreeCAD' not in sys.modules; print('ok')")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
