#!/usr/bin/env bash
# Installs what Sketch2CAD needs, idempotently: Debian's FreeCAD and Xvfb, a virtual
# environment at .venv/ from Debian's python3.11 (the interpreter FreeCAD's modules are
# built for) holding this package (editable) and its dependencies, and a link of this
# repository into FreeCAD's user Mod folder. Fast when everything is already there.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)

need_apt=()
command -v freecadcmd >/dev/null 2>&1 || need_apt+=(freecad)
command -v xvfb-run >/dev/null 2>&1 || need_apt+=(xvfb)
if [ ${#need_apt[@]} -gt 0 ]; then
    echo "setup: installing Debian packages: ${need_apt[*]}"
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${need_apt[@]}" >/dev/null
fi

if [ ! -x .venv/bin/python ]; then
    echo "setup: creating .venv from /usr/bin/python3.11"
    /usr/bin/python3.11 -m venv .venv
fi
stamp=.venv/.sketch2cad-installed
if [ ! -f "$stamp" ] || [ pyproject.toml -nt "$stamp" ] || [ ! -x .venv/bin/sketch2cad ]; then
    echo "setup: installing Python packages into .venv (first time: a few minutes)"
    .venv/bin/python -m pip install -q --upgrade pip
    # torch first, pinned: the CPU build; an unpinned torch would pull a multi-GB CUDA build.
    .venv/bin/python -m pip install -q torch==2.13.0
    .venv/bin/python -m pip install -q -e ".[test]"
    touch "$stamp"
fi

# Link the repository root into FreeCAD's user Mod folder, as the Addon Manager would clone it.
MOD="${HOME}/.local/share/FreeCAD/Mod"
mkdir -p "$MOD"
if [ "$(readlink -f "$MOD/Sketch2CAD" 2>/dev/null)" != "$ROOT" ]; then
    rm -rf "$MOD/Sketch2CAD"
    ln -s "$ROOT" "$MOD/Sketch2CAD"
    echo "setup: linked $ROOT into $MOD/Sketch2CAD"
fi
