#!/bin/sh
# Installs the Debian packages Seiche needs (when run as root), or prints the exact
# apt-get line and stops. Then generates the build with premake.
# Used by `make demo` and `make test`; safe to run again (it only installs what is missing).
set -eu

PACKAGES="gcc g++ make premake4 pkg-config libglfw3-dev libepoxy-dev liblua5.4-dev libbullet-dev \
libcglm-dev libstb-dev libcmocka-dev libimgui-dev libassimp-dev libegl-dev libgl-dev libgl1 libglx-mesa0 libgl1-mesa-dri libegl-mesa0 \
xvfb xauth gnuplot-nox ffmpeg clang-14 libclang-rt-14-dev"

missing=""
for p in $PACKAGES; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing="$missing $p"
    fi
done

if [ -n "$missing" ]; then
    if [ "$(id -u)" = 0 ]; then
        echo "setup: installing:$missing"
        export DEBIAN_FRONTEND=noninteractive
        apt-get update -q >/dev/null
        # shellcheck disable=SC2086
        apt-get install -y -q --no-install-recommends $missing >/dev/null
    else
        echo "setup: these Debian packages are missing:$missing"
        echo "setup: install them as root, then run make again:"
        echo "    sudo apt-get install -y$missing"
        exit 1
    fi
fi
