# SPDX-License-Identifier: LGPL-2.1-or-later
"""The layers import only downward (Sketch2CADWorkbench/README.md), and the core runs
without FreeCAD: only the FreeCAD layer imports it."""

import ast
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "Sketch2CADWorkbench"
# Lowest first; a module may import its own layer and those below, never above. Layers
# of one rank (datagen and inference; training and the FreeCAD layer) do not import
# each other.
LAYERS = [
    {"Sketch2CADWorkbench.brep"},
    {"Sketch2CADWorkbench.render"},
    {"Sketch2CADWorkbench.sketch"},
    {"datagen", "Sketch2CADWorkbench.inference"},
    {"training", "Sketch2CADWorkbench.freecad_layer"},
    {"Sketch2CADWorkbench.cli"},
]
FREECAD_LAYER = {
    "Sketch2CADWorkbench.freecad_layer",
    "Sketch2CADWorkbench.commands",
    "Sketch2CADWorkbench.Init",
    "Sketch2CADWorkbench.InitGui",
}
FREECAD_MODULES = {"FreeCAD", "FreeCADGui", "Part", "pivy"}


def _module(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path) -> set[str]:
    """The absolute names `path` imports (relative imports resolved)."""
    mod = _module(path)
    return _imports_of(
        path.read_text(), mod if path.name == "__init__.py" else mod.rpartition(".")[0]
    )


def _imports_of(source: str, package: str) -> set[str]:
    names = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            names |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                names.add(".".join(base + ([node.module] if node.module else [])))
            elif node.module:
                names.add(node.module)
    return names


def _layer(name: str):
    """(rank, group) of a module name, or None outside the layers."""
    for rank, group in enumerate(LAYERS):
        for prefix in group:
            if name == prefix or name.startswith(prefix + "."):
                return rank, prefix
    if name.startswith("Sketch2CADWorkbench.commands"):
        return LAYERS.index(
            {"training", "Sketch2CADWorkbench.freecad_layer"}
        ), "Sketch2CADWorkbench.freecad_layer"
    return None


def _sources():
    for top in (PACKAGE, ROOT / "datagen", ROOT / "training"):
        yield from top.rglob("*.py")


def test_every_import_goes_down_the_layers():
    upward = []
    for f in _sources():
        here = _layer(_module(f))
        if here is None:
            continue
        for name in _imports(f):
            there = _layer(name)
            if there is None:
                continue
            if there[0] > here[0] or (there[0] == here[0] and there[1] != here[1]):
                upward.append(f"{_module(f)} imports {name}")
    assert upward == []


def _exists(name: str) -> bool:
    """Whether the dotted name is a module or package of ours."""
    base = ROOT.joinpath(*name.split("."))
    return base.with_suffix(".py").is_file() or (base / "__init__.py").is_file()


def test_every_import_of_our_own_modules_names_one_that_exists():
    # a relative import one level short (a module moved into a subpackage) only fails
    # when that line runs, which in the FreeCAD layer is inside FreeCAD
    ours = ("Sketch2CADWorkbench", "datagen", "training")
    missing = [
        f"{_module(f)} imports {name}"
        for f in _sources()
        for name in _imports(f)
        if name.split(".")[0] in ours and not _exists(name)
    ]
    assert missing == []


def test_every_module_is_in_a_layer():
    loose = [
        _module(f)
        for f in _sources()
        if _layer(_module(f)) is None
        and _module(f) not in FREECAD_LAYER
        and _module(f) != "Sketch2CADWorkbench"
    ]
    assert loose == []


def test_only_the_freecad_layer_imports_freecad():
    offenders = []
    for f in _sources():
        mod = _module(f)
        if any(mod == p or mod.startswith(p + ".") for p in FREECAD_LAYER):
            continue
        if {n.split(".")[0] for n in _imports(f)} & FREECAD_MODULES:
            offenders.append(mod)
    assert offenders == []


def test_the_checker_resolves_relative_imports_to_their_layer():
    # what the kernel importing the renderer looks like to the first test
    (name,) = _imports_of("from ..render import camera\n", "Sketch2CADWorkbench.brep")
    assert name == "Sketch2CADWorkbench.render"
    assert _layer(name)[0] > _layer("Sketch2CADWorkbench.brep.operators")[0]


def test_only_the_cluster_module_imports_ray():
    # Ray is the optional extra `sketch2cad[cluster]`: nothing else may need it
    importers = [_module(f) for f in _sources() if "ray" in {n.split(".")[0] for n in _imports(f)}]
    assert importers == ["datagen.cluster"]


def test_the_core_the_command_line_and_training_import_without_ray():
    code = (
        "import sys; sys.modules['ray'] = None\n"  # import ray would raise
        "import Sketch2CADWorkbench.cli, Sketch2CADWorkbench.cli.datagen, datagen.parallel, "
        "datagen.cluster, training.train, Sketch2CADWorkbench.inference.interpret"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr


def test_core_imports_and_builds_without_freecad_on_the_path():
    code = (
        "import sys; import Sketch2CADWorkbench.brep.operators, Sketch2CADWorkbench.cli; "
        "assert 'FreeCAD' not in sys.modules; print('ok')"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
