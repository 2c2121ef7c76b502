#!/bin/sh
# Installs what the peer comparison needs (make bench-peers): Mesa's llvmpipe with a headless
# EGL (surfaceless platform) from Debian, and moderngl + matplotlib into the project's .venv.
# Needs root for apt-get (or sudo); never needed by `make test`.
set -eu
VENV=${VENV:-.venv}
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
PKGS="libegl1 libegl-mesa0 libgl1-mesa-dri libgbm1"
if ! dpkg -s $PKGS >/dev/null 2>&1; then
    $SUDO apt-get update -q
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends $PKGS
fi
"$VENV/bin/python" -m pip install -q -r bench/requirements-bench.txt
