# SPDX-License-Identifier: LGPL-2.1-or-later
"""The wheel holds what the package reads at run time: built from the sources, installed
into a fresh virtual environment, it interprets an example session with the weights it
carries and finds the workbench's icons.

The environment reuses the dependencies already installed (the folder torch imports from,
put on its path by a .pth file) instead of downloading them; nothing else of this checkout
is on its path, so the code that runs is the wheel's."""

import json
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
import torch

from Sketch2CADWorkbench.brep.protocol import load

ROOT = Path(__file__).resolve().parents[1]
SOURCES = ("pyproject.toml", "README.md", "LICENSE", "Sketch2CADWorkbench", "datagen", "training")
SESSION = ROOT / "examples" / "sessions" / "hammer.json"

pytestmark = pytest.mark.slow


def _run(*args: str | Path, cwd: Path, env: dict | None = None) -> str:
    done = subprocess.run(
        [str(a) for a in args], cwd=cwd, env=env, capture_output=True, text=True, timeout=900
    )
    assert done.returncode == 0, f"{args}:\n{done.stdout}\n{done.stderr}"
    return done.stdout


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """The wheel, built from a copy of the sources (the checkout stays as it was) with the
    build backend already installed (no download)."""
    tmp = tmp_path_factory.mktemp("wheel")
    src = tmp / "src"
    src.mkdir()
    for name in SOURCES:
        copy = shutil.copytree if (ROOT / name).is_dir() else shutil.copyfile
        ignore = {"ignore": shutil.ignore_patterns("__pycache__")} if (ROOT / name).is_dir() else {}
        copy(ROOT / name, src / name, **ignore)
    _run(
        sys.executable,
        "-m",
        "pip",
        "wheel",
        "--no-deps",
        "--no-build-isolation",
        "--no-index",
        "-w",
        tmp / "dist",
        src,
        cwd=tmp,
    )
    (built,) = (tmp / "dist").glob("sketch2cad-*.whl")
    return built


def test_the_wheel_holds_the_weights_their_card_and_the_icons(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    weights = ROOT / "Sketch2CADWorkbench" / "inference" / "weights"
    icons = ROOT / "Sketch2CADWorkbench" / "resources" / "icons"
    for path in [*weights.iterdir(), *icons.glob("*.svg")]:
        assert path.relative_to(ROOT).as_posix() in names, path.name


def test_the_installed_wheel_interprets_an_example_session(wheel, tmp_path):
    venv = tmp_path / "venv"
    _run(
        sys.executable, "-m", "venv", "--without-pip", "--system-site-packages", venv, cwd=tmp_path
    )
    python = venv / "bin" / "python"
    site = Path(
        _run(
            python, "-c", "import sysconfig; print(sysconfig.get_path('purelib'))", cwd=tmp_path
        ).strip()
    )
    (site / "dependencies.pth").write_text(f"{Path(torch.__file__).resolve().parents[1]}\n")
    _run(
        sys.executable,
        "-m",
        "pip",
        "--python",
        python,
        "install",
        "--no-deps",
        "--no-index",
        wheel,
        cwd=tmp_path,
    )
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    where = _run(
        python,
        "-c",
        "import Sketch2CADWorkbench.inference.weights as w, Sketch2CADWorkbench as s; "
        "print(w.DEFAULT_WEIGHTS); print(s.__file__)",
        cwd=tmp_path,
        env=env,
    )
    assert all(line.startswith(str(venv)) for line in where.split()), where
    _run(
        venv / "bin" / "sketch2cad",
        "interpret",
        SESSION,
        "--protocol",
        tmp_path / "read.json",
        cwd=tmp_path,
        env=env,
    )
    steps = len(json.loads(SESSION.read_text())["steps"])
    assert len(load(tmp_path / "read.json").operations) == steps
