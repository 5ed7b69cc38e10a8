# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad`: every command listed, and only the asked-for command's module loaded."""

import subprocess
import sys

CODE = """
import sys
from Sketch2CADWorkbench.cli import main
try:
    main(sys.argv[1:])
except SystemExit:
    pass
print("LOADED", *sorted(m for m in ("torch", "cadquery", "vtk") if m in sys.modules))
"""


def run(*args) -> str:
    out = subprocess.run(
        [sys.executable, "-c", CODE, *args], capture_output=True, text=True, timeout=300
    )
    return out.stdout + out.stderr


def test_help_lists_every_command_without_loading_the_heavy_libraries():
    text = run("--help")
    for name in (
        "build",
        "demo",
        "datagen",
        "train",
        "eval",
        "interpret",
        "diagnose",
        "option-scan",
        "model-card",
        "head-recovery",
        "oracle",
        "extrusion-bound",
    ):
        assert f"    {name}" in text, name
    assert "LOADED\n" in text or text.rstrip().endswith("LOADED"), text


def test_a_command_loads_its_own_module_and_parses_its_options():
    text = run("train", "--help")
    assert "--minutes" in text and "torch" in text.split("LOADED")[-1]
