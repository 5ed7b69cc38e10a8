#!/usr/bin/env bash
# Usage: scripts/chroot.sh SUITE COMMAND...
#
# Runs COMMAND (a bash command line) in a Debian SUITE chroot, in a copy of this checkout's
# working tree at /sketch2cad: trixie carries FreeCAD 1.0 (Qt5, Python 3.13), forky
# FreeCAD 1.1 (Qt6, PySide6, Python 3.14). The first time, the chroot is built with
# debootstrap (about a minute) under ${SKETCH2CAD_CHROOTS:-/var/cache/sketch2cad/chroots},
# outside the checkout so that every clone reuses it. Before COMMAND, this checkout's own
# scripts/setup.sh runs inside it, as on the host: FreeCAD, Xvfb and the dependencies the
# workbench's installer puts into FreeCAD's user folder (torch from Debian's python3-torch,
# since PyPI has only CUDA builds for these Pythons). Needs root (debootstrap, mount).
set -euo pipefail
SUITE=${1:?usage: scripts/chroot.sh SUITE COMMAND...}
shift
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BASE=${SKETCH2CAD_CHROOTS:-/var/cache/sketch2cad/chroots}
DIR="$BASE/$SUITE"
MIRROR=${SKETCH2CAD_MIRROR:-http://deb.debian.org/debian}
[ "$(id -u)" -eq 0 ] || { echo "chroot.sh: needs root (debootstrap and mount)" >&2; exit 2; }
mkdir -p "$BASE"

# One run at a time per chroot: a second waits instead of unmounting under the first.
exec 9>"$BASE/$SUITE.lock"
flock 9

if [ ! -f "$DIR/.sketch2cad-bootstrapped" ]; then
    command -v debootstrap >/dev/null || {
        apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq debootstrap >/dev/null; }
    echo "chroot.sh: building the $SUITE chroot in $DIR"
    rm -rf --one-file-system "$DIR"
    script=/usr/share/debootstrap/scripts/$SUITE
    [ -e "$script" ] || script=/usr/share/debootstrap/scripts/sid  # a suite newer than this debootstrap
    debootstrap --variant=minbase "$SUITE" "$DIR" "$MIRROR" "$script" >"$BASE/$SUITE.debootstrap.log" 2>&1 \
        || { tail -20 "$BASE/$SUITE.debootstrap.log" >&2; exit 1; }
    touch "$DIR/.sketch2cad-bootstrapped"
fi

# The host's name service, CA bundle and pip settings, or apt and pip cannot reach the registries.
cp /etc/resolv.conf "$DIR/etc/resolv.conf"
# A testing suite's Release file can outlive its Valid-Until on a mirror that lags.
echo 'Acquire::Check-Valid-Until "false";' >"$DIR/etc/apt/apt.conf.d/99sketch2cad"
mkdir -p "$DIR/etc/ssl/certs"
cp /etc/ssl/certs/ca-certificates.crt "$DIR/etc/ssl/certs/sketch2cad-host-ca.crt"
[ -f /etc/pip.conf ] && sed 's#^cert *=.*#cert = /etc/ssl/certs/sketch2cad-host-ca.crt#' /etc/pip.conf >"$DIR/etc/pip.conf"

mounted=()
cleanup() {
    for ((i = ${#mounted[@]} - 1; i >= 0; i--)); do umount -l "${mounted[$i]}" 2>/dev/null || true; done
}
trap cleanup EXIT
bind() {  # bind SOURCE TARGET-inside-the-chroot
    mkdir -p "$DIR$2"
    mountpoint -q "$DIR$2" || { mount --bind "$1" "$DIR$2"; mounted+=("$DIR$2"); }
}
bind /proc /proc
bind /dev /dev
bind /dev/pts /dev/pts
bind /dev/shm /dev/shm
# A copy of the working tree, not a bind mount: the chroot's .bin/ and caches stay its own.
rm -rf --one-file-system "$DIR/sketch2cad"
mkdir -p "$DIR/sketch2cad"
tar -C "$ROOT" --exclude=./.bin --exclude=./.venv --exclude=./data --exclude=./runs --exclude=./out \
    --exclude=__pycache__ -cf - . | tar -C "$DIR/sketch2cad" -xf -

ca=/etc/ssl/certs/sketch2cad-host-ca.crt
chroot "$DIR" /usr/bin/env -i HOME=/root LANG=C.UTF-8 TERM=dumb CI="${CI:-}" \
    PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    PIP_CERT=$ca SSL_CERT_FILE=$ca REQUESTS_CA_BUNDLE=$ca PIP_DEFAULT_TIMEOUT=180 \
    PIP_DISABLE_PIP_VERSION_CHECK=1 SKETCH2CAD_TORCH=debian SKETCH2CAD_EXTRAS=test \
    bash -c 'set -e; cd /sketch2cad; bash scripts/setup.sh; '"$*"
