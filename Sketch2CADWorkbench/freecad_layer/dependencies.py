# SPDX-License-Identifier: LGPL-2.1-or-later
"""The workbench's Python dependencies: which are missing, and installing them with the
Python that FreeCAD itself runs.

FreeCAD ships neither cadquery, torch nor VTK, and the Addon Manager pip-installs only
the packages on its allow-list (numpy, scipy and matplotlib are; cadquery, vtk, torch and
opencv are not). So the workbench keeps a folder of its own per Python version,
`<UserAppData>/Sketch2CAD/py3XY` (`FreeCAD.getUserAppDataDir()`: per FreeCAD version
from 1.1 on), filled by `pip install --target` run with FreeCAD's interpreter, as the
Addon Manager fills its AdditionalPythonPackages. `env.bootstrap()` puts that folder at
the front of sys.path. torch is not installed there when the system already has one in
the supported range (Debian's CPU-only python3-torch, say); else it comes from a CPU
index (PyPI's Linux torch is a CUDA build of several GB), configurable.

The same `install()` runs behind the workbench's Install button and behind the
developers' `scripts/setup.sh` (through `scripts/install_dependencies.py` in freecadcmd).
Only the standard library here: this runs before numpy may be imported.
"""

import importlib.util
import os
import re
import shutil
import subprocess
import sys
import tempfile
import tomllib
from collections.abc import Callable
from dataclasses import dataclass, field

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PYPROJECT = os.path.join(ROOT, "pyproject.toml")
PARAMETERS = "User parameter:BaseApp/Preferences/Mod/Sketch2CAD"
# Where a CPU-only torch comes from when the system has none (Linux and Windows; macOS
# wheels on PyPI are CPU builds already).
CPU_TORCH_INDEX = "https://download.pytorch.org/whl/cpu"
# The module each PyPI distribution is imported as, where the two names differ.
IMPORT_NAMES = {"opencv-contrib-python-headless": "cv2", "pytest": "pytest"}
STAMP = ".sketch2cad-requirements"


class InstallError(RuntimeError):
    """pip failed, or no interpreter matching FreeCAD's could be found; says which."""


@dataclass
class InstallPlan:
    """What `install` will do: which interpreter runs pip, into which folder, what."""

    python: str
    target: str
    requirements: list[str]
    torch_index: str = ""
    skipped: list[str] = field(default_factory=list)  # already on the system (torch)

    def pip_command(self, into: str) -> list[str]:
        cmd = [
            self.python,
            "-m",
            "pip",
            "install",
            "--no-input",
            "--progress-bar",
            "off",
            "--disable-pip-version-check",
            "--target",
            into,
        ]
        if self.torch_index:
            cmd += ["--extra-index-url", self.torch_index]
        return cmd + self.requirements


def python_tag(version=None) -> str:
    """'py311' for Python 3.11: the folder name, one per interpreter version."""
    major, minor = (version or sys.version_info)[:2]
    return f"py{major}{minor}"


def requirements(extras: tuple = (), pyproject: str = PYPROJECT) -> list[str]:
    """The dependencies pyproject.toml names (the one list), plus those of `extras`."""
    with open(pyproject, "rb") as f:
        project = tomllib.load(f)["project"]
    reqs = list(project["dependencies"])
    for extra in extras:
        reqs += project["optional-dependencies"][extra]
    return reqs


def distribution(requirement: str) -> str:
    """'torch>=2.6,<3' -> 'torch'."""
    return re.split(r"[\s<>=!~;\[]", requirement.strip(), maxsplit=1)[0]


def import_name(requirement: str) -> str:
    name = distribution(requirement)
    return IMPORT_NAMES.get(name, name.replace("-", "_"))


def missing(extras: tuple = ()) -> list[str]:
    """The distributions of `requirements(extras)` that this interpreter cannot import."""
    return [
        distribution(r)
        for r in requirements(extras)
        if importlib.util.find_spec(import_name(r)) is None
    ]


def find_python() -> str:
    """The interpreter of this Python's version to run pip with.

    Inside FreeCAD `sys.executable` is often FreeCAD itself (Debian, the AppImage), so,
    as the Addon Manager does, look for `python3.X` beside it and in its prefix.

    Raises:
        InstallError: none of the candidates is a Python of this version.
    """
    major, minor = sys.version_info[:2]
    names = [f"python{major}.{minor}", f"python{major}", "python"]
    exe = ".exe" if os.name == "nt" else ""
    dirs = [
        os.path.dirname(sys.executable),
        os.path.join(sys.prefix, "bin"),
        sys.prefix,
        os.path.join(sys.base_prefix, "bin"),
        sys.base_prefix,
    ]
    candidates = [sys.executable] + [os.path.join(d, n + exe) for d in dirs for n in names]
    candidates += [p for p in (shutil.which(n) for n in names) if p]
    for path in dict.fromkeys(candidates):
        # FreeCAD's own binary runs `-c` code too, but not `-m pip`
        if (
            os.path.basename(path).lower().startswith("python")
            and os.path.isfile(path)
            and _python_version(path) == (major, minor)
        ):
            return path
    raise InstallError(
        f"found no python{major}.{minor} beside FreeCAD ({sys.executable}) "
        f"to run pip with; set the Python in Sketch2CAD's preferences"
    )


def _python_version(path: str) -> tuple | None:
    try:
        out = subprocess.run(
            [path, "-c", "import sys; print(*sys.version_info[:2])"],
            capture_output=True,
            text=True,
            timeout=30,
            env=_clean_env(),
        )
    except (OSError, subprocess.TimeoutExpired):
        return None
    parts = out.stdout.split()
    return tuple(int(p) for p in parts) if out.returncode == 0 and len(parts) == 2 else None


def _clean_env() -> dict:
    """The environment of a fresh interpreter: no PYTHONPATH or PYTHONHOME of FreeCAD's."""
    return {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}


def system_has(python: str, requirement: str) -> bool:
    """Whether `python`, on its own sys.path, already imports a version of the
    requirement's distribution that the requirement admits (Debian's python3-torch)."""
    name, spec = distribution(requirement), requirement[len(distribution(requirement)) :]
    code = (
        "import importlib.metadata as m, sys\n"
        f"v = m.version({name!r})\n"
        "from packaging.specifiers import SpecifierSet\n"
        f"sys.exit(0 if SpecifierSet({spec.strip()!r}).contains(v.split('+')[0]) else 3)"
    )
    # packaging is pip's own vendored copy when the system has none
    code = code.replace(
        "from packaging.specifiers",
        "try:\n    import packaging.specifiers\nexcept ImportError:\n"
        "    import pip._vendor.packaging.specifiers as _p; "
        "sys.modules['packaging.specifiers'] = _p\nfrom packaging.specifiers",
    )
    run = subprocess.run([python, "-c", code], capture_output=True, env=_clean_env(), timeout=60)
    return run.returncode == 0


def plan(
    target: str,
    extras: tuple = (),
    python: str | None = None,
    torch_spec: str | None = None,
    torch_index: str | None = None,
) -> InstallPlan:
    """What to install into `target`.

    Args:
        target: the folder (created by `install`; replaced whole on success).
        extras: pyproject's optional groups to add (the developers' "test").
        python: the interpreter to run pip with; default `find_python()`.
        torch_spec: replaces pyproject's torch requirement (e.g. "torch==2.13.0").
        torch_index: extra index for torch; default CPU_TORCH_INDEX except on macOS,
            "" for none.
    """
    python = python or find_python()
    if torch_index is None:
        torch_index = "" if sys.platform == "darwin" else CPU_TORCH_INDEX
    reqs, skipped = [], []
    for req in requirements(extras):
        if distribution(req) == "torch":
            if system_has(python, req):
                skipped.append(req)
                continue
            req = torch_spec or req
        reqs.append(req)
    uses_index = any(distribution(r) == "torch" for r in reqs)
    return InstallPlan(python, target, reqs, torch_index if uses_index else "", skipped)


def is_installed(p: InstallPlan) -> bool:
    """`target` holds exactly this plan's requirements (written by a finished install)."""
    try:
        with open(os.path.join(p.target, STAMP)) as f:
            return f.read().split("\n") == sorted(p.requirements)
    except OSError:
        return False


def install(p: InstallPlan, on_line: Callable[[str], None] = print) -> None:
    """Run the plan: pip into a new folder beside `target`, which replaces `target` only
    when pip succeeded, so a failed or interrupted install leaves the old one working.

    Args:
        p: from `plan`.
        on_line: called with each line pip prints (a progress display).

    Raises:
        InstallError: pip failed; the message ends with what pip said last.
    """
    parent = os.path.dirname(os.path.abspath(p.target))
    os.makedirs(parent, exist_ok=True)
    for stale in os.listdir(parent):  # left by an install that was killed
        if stale.startswith(os.path.basename(p.target) + ".partial-"):
            shutil.rmtree(os.path.join(parent, stale), ignore_errors=True)
    work = tempfile.mkdtemp(prefix=os.path.basename(p.target) + ".partial-", dir=parent)
    try:
        _run_pip(p.pip_command(work), on_line)
        with open(os.path.join(work, STAMP), "w") as f:
            f.write("\n".join(sorted(p.requirements)))
        old = None
        if os.path.exists(p.target):
            old = tempfile.mkdtemp(prefix=os.path.basename(p.target) + ".partial-", dir=parent)
            os.replace(p.target, os.path.join(old, "old"))
        os.replace(work, p.target)
        if old:
            shutil.rmtree(old, ignore_errors=True)
    finally:
        if os.path.isdir(work):
            shutil.rmtree(work, ignore_errors=True)


def _run_pip(cmd: list, on_line: Callable[[str], None]) -> None:
    on_line("$ " + " ".join(cmd))
    proc = subprocess.Popen(
        cmd,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        env=_clean_env(),
        bufsize=1,
    )
    tail = []
    for line in proc.stdout:
        line = line.rstrip()
        tail = (tail + [line])[-15:]
        on_line(line)
    if proc.wait() != 0:
        raise InstallError(f"pip exited with {proc.returncode}:\n" + "\n".join(tail))


def manual_command(p: InstallPlan) -> str:
    """The shell command that does what `install` does, for a user who declined."""
    return " ".join(_quote(a) for a in p.pip_command(p.target))


def _quote(arg: str) -> str:
    return (
        arg
        if re.fullmatch(r"[\w@%+=:,./<>-]+", arg) and not set("<>") & set(arg)
        else "'" + arg.replace("'", "'\\''") + "'"
    )


def setting(name: str, default: str) -> str:
    """A user setting: the environment's SKETCH2CAD_<NAME> (for scripts and CI) first, then
    FreeCAD's parameter `name` in Sketch2CAD's preferences, then `default`."""
    env = os.environ.get("SKETCH2CAD_" + re.sub(r"(?<!^)(?=[A-Z])", "_", name).upper())
    if env is not None:
        return env
    import FreeCAD

    return FreeCAD.ParamGet(PARAMETERS).GetString(name, "") or default


def folder() -> str:
    """This FreeCAD's dependency folder: `<UserAppData>/Sketch2CAD/py3XY`, or the
    DependencyFolder setting (which is used as it is, whatever the Python version)."""
    import FreeCAD

    default = os.path.join(FreeCAD.getUserAppDataDir(), "Sketch2CAD", python_tag())
    return os.path.abspath(os.path.expanduser(setting("DependencyFolder", default)))


def user_plan(extras: tuple = ()) -> InstallPlan:
    """The plan for this FreeCAD: its folder, its interpreter, the torch settings
    (TorchRequirement, TorchIndex: "" for none)."""
    index = setting("TorchIndex", "default")
    return plan(
        folder(),
        extras,
        python=setting("Python", "") or None,
        torch_spec=setting("TorchRequirement", "") or None,
        torch_index=None if index == "default" else index,
    )
