# SPDX-License-Identifier: LGPL-2.1-or-later
"""The dependency installer behind the workbench's Install button and scripts/setup.sh
(its FreeCAD-free part; the real install runs in tests/freecad/test_addon_install.py)."""

import os
import shlex
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from Sketch2CADWorkbench.freecad_layer import dependencies as deps

ROOT = Path(__file__).resolve().parents[2]


def fake_python(tmp_path: Path, body: str) -> str:
    """An executable named python3.X that runs `body` (sh) with the real interpreter as $PY."""
    path = tmp_path / f"python{sys.version_info[0]}.{sys.version_info[1]}"
    path.write_text(f"#!/bin/sh\nPY={shlex.quote(sys.executable)}\n{body}\n")
    path.chmod(0o755)
    return str(path)


def with_torch(tmp_path: Path, version: str) -> str:
    """A python that sees a (metadata-only) torch of `version` and nothing of the tests'."""
    site = tmp_path / "site"
    (site / f"torch-{version}.dist-info").mkdir(parents=True)
    (site / f"torch-{version}.dist-info" / "METADATA").write_text(
        f"Metadata-Version: 2.1\nName: torch\nVersion: {version}\n"
    )
    return fake_python(tmp_path, f'PYTHONPATH={shlex.quote(str(site))} exec "$PY" "$@"')


def test_package_xml_names_the_pypi_distributions_pyproject_installs():
    ns = {"p": "https://wiki.freecad.org/Package_Metadata"}
    root = ET.parse(ROOT / "package.xml").getroot()
    named = [d.text for d in root.iterfind(".//p:workbench/p:depend[@type='python']", ns)]
    assert sorted(named) == sorted(deps.distribution(r) for r in deps.requirements())


def test_requirements_come_from_pyproject_with_the_extras_asked_for():
    base = deps.requirements()
    assert any(deps.distribution(r) == "cadquery" for r in base)
    assert "pytest" not in map(deps.distribution, base)
    assert "pytest" in map(deps.distribution, deps.requirements(("test",)))


def test_missing_names_what_this_interpreter_cannot_import(tmp_path, monkeypatch):
    pyproject = tmp_path / "pyproject.toml"
    pyproject.write_text(
        '[project]\ndependencies = ["numpy>=1", "no-such-package-s2c==1.0", '
        '"opencv-contrib-python-headless"]\n'
    )
    monkeypatch.setattr(deps, "PYPROJECT", str(pyproject))
    monkeypatch.setattr(deps.requirements, "__defaults__", ((), str(pyproject)))
    assert deps.missing() == ["no-such-package-s2c"]  # cv2 is imported as cv2


def test_find_python_is_an_interpreter_of_this_version():
    python = deps.find_python()
    out = subprocess.run(
        [python, "-c", "import sys; print(sys.version_info[:2])"], capture_output=True, text=True
    )
    assert out.stdout.strip() == str(tuple(sys.version_info[:2]))


def test_a_system_torch_in_range_is_used_not_installed(tmp_path):
    plan = deps.plan(str(tmp_path / "deps"), python=with_torch(tmp_path, "2.6.0"))
    assert "torch" not in map(deps.distribution, plan.requirements)
    assert [deps.distribution(r) for r in plan.skipped] == ["torch"]
    assert plan.torch_index == ""


def test_without_a_usable_torch_the_cpu_build_is_asked_for(tmp_path):
    old_torch = with_torch(tmp_path, "1.13.1")
    plan = deps.plan(str(tmp_path / "deps"), python=old_torch)
    assert any(deps.distribution(r) == "torch" for r in plan.requirements)
    if sys.platform != "darwin":
        assert plan.torch_index == deps.CPU_TORCH_INDEX
        assert plan.pip_command("X")[plan.pip_command("X").index("--extra-index-url") :][:2] == [
            "--extra-index-url",
            deps.CPU_TORCH_INDEX,
        ]
    pinned = deps.plan(
        str(tmp_path / "deps"), python=old_torch, torch_spec="torch==2.13.0", torch_index=""
    )
    assert "torch==2.13.0" in pinned.requirements and "--extra-index-url" not in pinned.pip_command(
        "X"
    )


def installing_python(tmp_path: Path, fail: bool) -> str:
    """A python whose `-m pip install ... --target DIR` makes DIR/fakepkg, or fails."""
    return fake_python(
        tmp_path,
        (
            'case "$*" in *"-m pip install"*) ;; *) exec "$PY" "$@";; esac\n'
            + (
                'echo "ERROR: No matching distribution found for cadquery"; exit 1\n'
                if fail
                else 'while [ "$1" != "--target" ]; do shift; done\n'
                'mkdir -p "$2/fakepkg" && echo ok > "$2/fakepkg/__init__.py"; '
                "echo Successfully installed"
            )
        ),
    )


def test_install_replaces_the_folder_only_when_pip_succeeded(tmp_path):
    target = tmp_path / "Sketch2CAD" / "py3x"
    target.mkdir(parents=True)
    (target / "old.txt").write_text("the working installation")
    failing = deps.InstallPlan(installing_python(tmp_path, fail=True), str(target), ["cadquery"])
    with pytest.raises(deps.InstallError, match="No matching distribution found for cadquery"):
        deps.install(failing, on_line=lambda line: None)
    assert (target / "old.txt").read_text() == "the working installation"
    assert sorted(os.listdir(target.parent)) == ["py3x"]  # no partial folder left
    assert not deps.is_installed(failing)

    lines = []
    ok = deps.InstallPlan(installing_python(tmp_path, fail=False), str(target), ["b", "a"])
    deps.install(ok, on_line=lines.append)
    assert (target / "fakepkg" / "__init__.py").exists() and not (target / "old.txt").exists()
    assert "Successfully installed" in lines and lines[0].startswith("$ ")
    assert deps.is_installed(ok)
    assert not deps.is_installed(deps.InstallPlan(ok.python, str(target), ["a", "b", "c"]))
    assert sorted(os.listdir(target.parent)) == ["py3x"]


def test_the_manual_command_is_one_a_shell_runs_as_is(tmp_path):
    plan = deps.InstallPlan(
        "/usr/bin/python3.11",
        str(tmp_path / "my deps"),
        ["torch>=2.6,<3", "vtk"],
        torch_index=deps.CPU_TORCH_INDEX,
    )
    argv = shlex.split(deps.manual_command(plan))
    assert argv == plan.pip_command(plan.target)
