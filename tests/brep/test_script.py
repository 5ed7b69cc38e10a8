# SPDX-License-Identifier: LGPL-2.1-or-later
"""The CadQuery script of a protocol rebuilds the core's solid, run where only cadquery
(and what it needs) is installed."""

import importlib.metadata as metadata
import runpy
import subprocess
import sys
from pathlib import Path

import cadquery as cq
import pytest
from packaging.requirements import Requirement
from round_fixtures import round_protocols

from Sketch2CADWorkbench.brep.features import mismatch, plan_protocol
from Sketch2CADWorkbench.brep.protocol import load
from Sketch2CADWorkbench.brep.script import cadquery_script

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "examples" / "protocols").glob("*.json"))
TOL = 1e-6


def _closure(name: str) -> list[metadata.Distribution]:
    """The installed distribution `name` and every one it requires (extras left out)."""
    seen: dict[str, metadata.Distribution] = {}
    todo = [name]
    while todo:
        dist = metadata.distribution(todo.pop())
        key = dist.metadata["Name"].lower().replace("_", "-")
        if key in seen:
            continue
        seen[key] = dist
        for text in dist.requires or []:
            req = Requirement(text)
            if req.marker is None or req.marker.evaluate({"extra": ""}):
                todo.append(req.name)
    return list(seen.values())


@pytest.fixture(scope="module")
def cadquery_only(tmp_path_factory) -> Path:
    """A virtual environment holding only cadquery and its requirements (links to the
    installed copies: nothing is downloaded), run isolated (-I: no PYTHONPATH, no user
    site, not the current directory): this project is not importable there."""
    venv = tmp_path_factory.mktemp("cadquery-only")
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    site = next(venv.glob("lib/python*/site-packages"))
    for dist in _closure("cadquery"):
        tops = {Path(str(f)).parts[0] for f in dist.files or []}
        for top in tops:
            src = Path(dist.locate_file(top))
            if src.exists() and not (site / top).exists() and top not in ("..", "bin"):
                (site / top).symlink_to(src)
    return venv / "bin" / "python"


def test_example_scripts_rebuild_the_core_solids(cadquery_only, tmp_path):
    solids = {}
    for path in EXAMPLES:
        plan = plan_protocol(load(path))
        (tmp_path / f"{path.stem}.py").write_text(cadquery_script(plan, path.stem))
        solids[path.stem] = plan.solids[-1]
    driver = (
        "import runpy, sys, pathlib\n"
        "try:\n    import Sketch2CADWorkbench\nexcept ImportError:\n    pass\n"
        "else:\n    sys.exit('the project is importable')\n"
        "for p in sorted(pathlib.Path(sys.argv[1]).glob('*.py')):\n"
        "    runpy.run_path(str(p))['result'].exportBrep(str(p.with_suffix('.brep')))\n"
    )
    subprocess.run(
        [str(cadquery_only), "-I", "-c", driver, str(tmp_path)], check=True, cwd=tmp_path
    )
    for name, core in solids.items():
        got = cq.Shape.importBrep(str(tmp_path / f"{name}.brep"))
        assert abs(got.Volume() - core.Volume()) <= TOL * core.Volume(), name
        assert mismatch(got, core) <= TOL, name


def test_script_names_the_steps_parameters():
    plan = plan_protocol(load(ROOT / "examples" / "protocols" / "lamp.json"))
    text = cadquery_script(plan, "lamp")
    # the profile c_p of step 3 with its control points as variables
    assert "cp1_r = 12.0" in text and "(cp1_r, cp1_h)" in text
    assert text.count("# Step ") == len(plan.features)
    compile(text, "lamp.py", "exec")


def test_scripts_of_rounds_and_chamfers_rebuild_the_core_solids(tmp_path):
    for name, protocol in round_protocols().items():
        plan = plan_protocol(protocol)
        path = tmp_path / "round.py"
        path.write_text(cadquery_script(plan, name))
        got = runpy.run_path(str(path))["result"]
        assert mismatch(got, plan.solids[-1]) <= TOL, name
