#!/usr/bin/env bash
# Installs what Sketch2CAD needs, idempotently, on Debian (12 on the host; 13 and testing in
# the chroots of scripts/chroot.sh): Debian's FreeCAD and Xvfb, a link of this checkout into
# FreeCAD's user Mod folder (as the Addon Manager clones an addon there), and then the
# workbench's Python dependencies through the workbench's own installer, the code behind
# its Install button (scripts/install_dependencies.py in freecadcmd), plus the test tools.
# Last, .bin/python and .bin/sketch2cad: FreeCAD's Python with that folder in front
# (and .bin/ray, Ray's command line).
# Fast when everything is already there.
#
# SKETCH2CAD_TORCH=pip (default): torch from the registry, pinned to 2.13.0 (this
# machine's CPU build); =debian: Debian's CPU-only python3-torch (PyPI has only CUDA
# builds for Python 3.13 and 3.14).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
TORCH=${SKETCH2CAD_TORCH:-pip}

SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
need_apt=()
command -v freecadcmd >/dev/null 2>&1 || need_apt+=(freecad)
command -v xvfb-run >/dev/null 2>&1 || need_apt+=(xvfb xauth)
command -v git >/dev/null 2>&1 || need_apt+=(git)
dpkg -s python3-pip >/dev/null 2>&1 || need_apt+=(python3-pip)
[ "$TORCH" = debian ] && { dpkg -s python3-torch >/dev/null 2>&1 || need_apt+=(python3-torch); }
if [ ${#need_apt[@]} -gt 0 ]; then
    echo "setup: installing Debian packages: ${need_apt[*]}"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends \
        "${need_apt[@]}" libxcursor1 >/dev/null
fi

# The Qt bindings FreeCAD recommends: its Addon Manager imports QtWebEngineWidgets at start
# and warns in the report view without them (`apt install freecad` brings them; the
# --no-install-recommends above does not). Package lists first where a machine has none.
apt-cache show freecad >/dev/null 2>&1 || $SUDO apt-get update -qq
fc_pkgs="freecad $(apt-cache depends freecad | awk '/Depends: freecad/ {print $2}' | sort -u)"
recommended=()
for pkg in $(apt-cache depends $fc_pkgs | awk '/Recommends: python3-pyside/ {print $2}' | sort -u); do
    dpkg -s "$pkg" >/dev/null 2>&1 || recommended+=("$pkg")
done
if [ ${#recommended[@]} -gt 0 ]; then
    echo "setup: installing the Qt bindings FreeCAD recommends: ${recommended[*]}"
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends \
        "${recommended[@]}" >/dev/null
fi

# What FreeCAD's GUI draws with and a desktop brings along: Qt's SVG image and icon
# plugins (without them Qt 6 draws FreeCAD's check boxes without a tick, and some icons
# not at all), for Qt 6 (qt6-svg-plugins) or Qt 5 (libqt5svg5); and what the GUI tests
# drive FreeCAD from outside with (tests/freecad/test_x_events.py): xdotool for real X
# mouse and key events, openbox as the window manager, xwd for screenshots.
svg=libqt5svg5
dpkg -l 'libqt6core6*' 2>/dev/null | grep -q '^ii' && svg=qt6-svg-plugins  # FreeCAD 1.1's Qt 6
gui=()
for pkg in $svg xdotool openbox x11-apps; do
    dpkg -s "$pkg" >/dev/null 2>&1 || gui+=("$pkg")
done
if [ ${#gui[@]} -gt 0 ]; then
    echo "setup: installing Qt's SVG plugins and the GUI tests' X tools: ${gui[*]}"
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends \
        "${gui[@]}" >/dev/null
fi

# FreeCAD's user folder (per version from FreeCAD 1.1 on) and its Mod link.
USERDATA=$(freecadcmd -c "import FreeCAD; print('USERDATA=' + FreeCAD.getUserAppDataDir())" 2>/dev/null \
           | sed -n 's/^USERDATA=//p' | tail -n 1)
[ -n "$USERDATA" ] || { echo "setup: freecadcmd did not say where its user folder is" >&2; exit 1; }
MOD="${USERDATA%/}/Mod"
mkdir -p "$MOD"
if [ "$(readlink -f "$MOD/Sketch2CAD" 2>/dev/null)" != "$ROOT" ]; then
    rm -rf "$MOD/Sketch2CAD"
    ln -s "$ROOT" "$MOD/Sketch2CAD"
    echo "setup: linked $ROOT into $MOD/Sketch2CAD"
fi

# The workbench's installer, as the Install button runs it.
# The test tools, the linters and the cluster extra (Ray: `datagen --ray` and its tests); the
# chroots, which run only tests/freecad, ask for "test" alone (no Ray wheels for Python 3.14).
export SKETCH2CAD_EXTRAS=${SKETCH2CAD_EXTRAS:-test,lint,cluster}
if [ "$TORCH" = pip ]; then
    export SKETCH2CAD_TORCH_REQUIREMENT=torch==2.13.0 SKETCH2CAD_TORCH_INDEX=""
fi
log=$(mktemp)
trap 'rm -f "$log"' EXIT
# The installer's own lines and pip's main ones, as they come (the first install takes minutes).
LANG=C.UTF-8 freecadcmd "$ROOT/scripts/install_dependencies.py" 2>&1 | tee "$log" \
    | grep --line-buffered -E '^install_dependencies|^    (Collecting|Successfully|ERROR)' || true
line=$(grep '^python=' "$log" | tail -n 1)
[ -n "$line" ] || { echo "setup: the dependency installer failed:" >&2; tail -n 30 "$log" >&2; exit 1; }
PY=${line#python=}; PY=${PY%% folder=*}
DEPS=${line##* folder=}

mkdir -p .bin
cat >.bin/python <<EOF
#!/bin/sh
# Made by scripts/setup.sh: FreeCAD's Python with the workbench's dependency folder in front.
PYTHONPATH="$DEPS:$ROOT\${PYTHONPATH:+:\$PYTHONPATH}" exec "$PY" "\$@"
EOF
printf '#!/bin/sh\nexec "%s/.bin/python" -m Sketch2CADWorkbench.cli "$@"\n' "$ROOT" >.bin/sketch2cad
# Ray's command line with that Python (`.bin/ray start --head`: README, "Past one machine").
printf '#!/bin/sh\nexec "%s/.bin/python" -m ray.scripts.scripts "$@"\n' "$ROOT" >.bin/ray
chmod +x .bin/python .bin/sketch2cad .bin/ray
