# SPDX-License-Identifier: LGPL-2.1-or-later
"""The CadQuery and build123d scripts of a protocol rebuild the core's solid, each run
where only its library (and what that needs) is installed."""

import dataclasses
import importlib.metadata as metadata
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import cadquery as cq
import numpy as np
import pytest
from packaging.requirements import Requirement
from round_fixtures import round_protocols

from Sketch2CADWorkbench.brep.features import (
    Plan,
    combined,
    feature_tool,
    mismatch,
    plan_protocol,
)
from Sketch2CADWorkbench.brep.protocol import AddSubPrism, Mode, Protocol, load
from Sketch2CADWorkbench.brep.script import protocol_script

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "examples" / "protocols").glob("*.json"))
TOL = 1e-6
# build123d and the OCCT binding it was compared with: another OCCT may draw a Boolean's
# intersection curves a little differently (pipe.json's volume is 5e-7 off with these).
BUILD123D = ("build123d==0.13.0", "cadquery-ocp-novtk==8.0.1.1.0")
# how the run writes each script's `result` to a BREP file `path`
EXPORT = {
    "cadquery": "result.exportBrep(path)",
    "build123d": "__import__('build123d').export_brep(result, path)",
}


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


def cadquery_only(tmp_path_factory) -> Path:
    """A virtual environment holding only cadquery and its requirements (links to the
    installed copies: nothing is downloaded)."""
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


def build123d_only(tmp_path_factory) -> Path:
    """A virtual environment holding only build123d and its requirements, installed from
    the package registry the first time (about a minute and 1 GB) and kept in the user's
    cache, outside the checkout, for the next runs."""
    cache = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "sketch2cad"
    tag = f"py{sys.version_info.major}.{sys.version_info.minor}"
    venv = cache / f"{BUILD123D[0].replace('==', '-')}-{tag}"
    if not (venv / "complete").exists():
        # built beside it and moved into place whole, so a run cut short or a second run
        # at the same time never leaves a half-installed one there
        shutil.rmtree(venv, ignore_errors=True)
        cache.mkdir(parents=True, exist_ok=True)
        new = cache / f"{venv.name}.{os.getpid()}"
        shutil.rmtree(new, ignore_errors=True)
        env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
        made = subprocess.run(
            [sys.executable, "-m", "venv", "--without-pip", str(new)],
            capture_output=True,
            text=True,
        )
        pip = [sys.executable, "-m", "pip", "--python", str(new / "bin" / "python")]
        if made.returncode == 0:
            made = subprocess.run(
                [*pip, "install", "--quiet", *BUILD123D], capture_output=True, text=True, env=env
            )
        if made.returncode != 0:
            shutil.rmtree(new, ignore_errors=True)
            pytest.fail(
                f"could not build the virtual environment holding only {' '.join(BUILD123D)} "
                f"(from the package registry, into {venv}): this test needs it.\n"
                + (made.stdout + made.stderr)[-3000:]
            )
        (new / "complete").touch()
        try:
            new.rename(venv)
        except OSError:  # another run has just put one there
            shutil.rmtree(new, ignore_errors=True)
    return venv / "bin" / "python"


VENVS = {"cadquery": cadquery_only, "build123d": build123d_only}


@pytest.fixture(scope="module")
def cases() -> dict[str, Plan]:
    """The examples' plans, the rounds' (fillets, chamfers and profiles across edges,
    tests/round_fixtures.py), and two step kinds no example has: an intersection (mixer's
    tall prism cut back to 30 mm), and a bevel whose crease leans off f's normal (as it
    does along a solid's edge that is not square to f: hammer's bevel of step 2 leaning
    3 degrees; its solid is its feature's, as the operators give none)."""
    plans = {path.stem: plan_protocol(load(path)) for path in EXAMPLES}
    for name, protocol in round_protocols().items():
        plans[f"round-{name.replace(' ', '-')}"] = plan_protocol(protocol)
    mixer = plans["mixer"].protocol
    top = mixer.operations[0]
    cut = AddSubPrism(top.face, top.polygon, 30.0, Mode.INTERSECT)
    plans["intersect"] = plan_protocol(Protocol(mixer.base, mixer.operations[:3] + (cut,)))
    hammer = plans["hammer"]
    bevel = hammer.features[2]
    lean = math.radians(3.0)
    crease = -math.cos(lean) * np.asarray(bevel.frame.normal) + math.sin(lean) * np.asarray(
        bevel.frame.u
    )
    leaning = dataclasses.replace(bevel, direction=tuple(crease))
    before = hammer.solids[1]
    plans["leaning-bevel"] = Plan(
        Protocol(hammer.protocol.base, hammer.protocol.operations[:2]),
        [*hammer.features[:2], leaning],
        [*hammer.solids[:2], combined(before, feature_tool(leaning, before), bevel.mode)],
    )
    return plans


@pytest.mark.slow
@pytest.mark.parametrize("library", list(VENVS))
def test_scripts_rebuild_the_core_solids_with_only_their_library(
    library, cases, tmp_path, tmp_path_factory
):
    python = VENVS[library](tmp_path_factory)
    for name, plan in cases.items():
        (tmp_path / f"{name}.py").write_text(protocol_script(plan, name, library))
    # run isolated (-I: no PYTHONPATH, no user site, not the current directory)
    driver = (
        "import runpy, sys, pathlib\n"
        "try:\n    import Sketch2CADWorkbench\nexcept ImportError:\n    pass\n"
        "else:\n    sys.exit('the project is importable')\n"
        "for p in sorted(pathlib.Path(sys.argv[1]).glob('*.py')):\n"
        "    result, path = runpy.run_path(str(p))['result'], str(p.with_suffix('.brep'))\n"
        f"    {EXPORT[library]}\n"
    )
    subprocess.run([str(python), "-I", "-c", driver, str(tmp_path)], check=True, cwd=tmp_path)
    for name, plan in cases.items():
        core = plan.solids[-1]
        got = cq.Shape.importBrep(str(tmp_path / f"{name}.brep"))
        assert abs(got.Volume() - core.Volume()) <= TOL * core.Volume(), name
        assert mismatch(got, core) <= TOL, name


@pytest.mark.parametrize("library", list(VENVS))
def test_script_names_the_steps_parameters(library, cases):
    plan = cases["lamp"]
    text = protocol_script(plan, "lamp", library)
    # the profile c_p of step 3 with its control points as variables
    assert "cp1_r = 12.0" in text and "(cp1_r, cp1_h)" in text
    assert text.count("# Step ") == len(plan.features)
    assert "Sketch2CADWorkbench" not in text
    compile(text, "lamp.py", "exec")
