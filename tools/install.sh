#!/bin/sh
# Installs a finished build into a prefix (`make install PREFIX=...` builds first, then
# runs this). Layout, for PREFIX=/usr/local:
#   lib/libseiche_fluid.so.X.Y.Z (+ .so.X, .so links), lib/libseiche_fluid.a
#   lib/libseiche_coupling.a, lib/libseiche_phys.a       the Bullet coupling, static
#   lib/pkgconfig/seiche-fluid.pc, seiche-coupling.pc
#   include/seiche/fluid/pbf.h, include/seiche/fluid/bullet/{coupling,phys}.h
#   bin/seiche, bin/seiche-bench                          (shaders are inside them)
#   share/seiche/scenes/*.lua, share/doc/seiche/*.md
# usage: tools/install.sh PREFIX [BUILD_DIR]   (DESTDIR is honoured, as make's convention)
set -eu
if [ $# -lt 1 ] || [ "$1" = "--help" ]; then
    echo "usage: tools/install.sh PREFIX [BUILD_DIR]" >&2
    exit 2
fi
prefix=$1
top=$(cd "$(dirname "$0")/.." && pwd)
build=${2:-$top/build}
dest=${DESTDIR:-}
case "$prefix" in
    /*) ;;
    *) echo "install: PREFIX must be an absolute path (got '$prefix')" >&2; exit 2 ;;
esac
version=$(sed -n 's/^#define PBF_VERSION_STRING "\(.*\)"$/\1/p' "$top/fluid/pbf.h")
major=${version%%.*}
[ -n "$version" ] || { echo "install: no PBF_VERSION_STRING in fluid/pbf.h" >&2; exit 2; }
for f in "$build/lib/libseiche_fluid.so" "$build/bin/libseiche_fluid.a" "$build/bin/seiche"; do
    [ -f "$f" ] || { echo "install: $f is missing: build first (make build)" >&2; exit 2; }
done

lib=$dest$prefix/lib
inc=$dest$prefix/include/seiche
mkdir -p "$lib/pkgconfig" "$inc/fluid/bullet" "$dest$prefix/bin" "$dest$prefix/share/seiche/scenes/assets" \
         "$dest$prefix/share/doc/seiche"

install -m 755 "$build/lib/libseiche_fluid.so" "$lib/libseiche_fluid.so.$version"
ln -sf "libseiche_fluid.so.$version" "$lib/libseiche_fluid.so.$major"
ln -sf "libseiche_fluid.so.$major" "$lib/libseiche_fluid.so"
for a in libseiche_fluid.a libseiche_coupling.a libseiche_phys.a; do
    install -m 644 "$build/bin/$a" "$lib/$a"
done
install -m 644 "$top/fluid/pbf.h" "$inc/fluid/pbf.h"
install -m 644 "$top/fluid/bullet/coupling.h" "$inc/fluid/bullet/coupling.h"
install -m 644 "$top/fluid/bullet/phys.h" "$inc/fluid/bullet/phys.h"
install -m 755 "$build/bin/seiche" "$dest$prefix/bin/seiche"
[ ! -f "$build/bin/seiche-bench" ] || install -m 755 "$build/bin/seiche-bench" "$dest$prefix/bin/seiche-bench"
install -m 644 "$top"/scripts/scenes/*.lua "$dest$prefix/share/seiche/scenes/"
install -m 644 "$top"/scripts/scenes/assets/* "$dest$prefix/share/seiche/scenes/assets/"
install -m 644 "$top"/docs/*.md "$dest$prefix/share/doc/seiche/"

cat >"$lib/pkgconfig/seiche-fluid.pc" <<EOF
prefix=$prefix
libdir=\${prefix}/lib
includedir=\${prefix}/include/seiche

Name: seiche-fluid
Description: Seiche real-time fluid: Position Based Fluids on OpenGL 4.3 compute shaders
Version: $version
Requires: epoxy
Libs: -L\${libdir} -lseiche_fluid
Libs.private: -lm
Cflags: -I\${includedir}
EOF
# Static archives: what they need (Bullet, the C++ runtime) is part of every link, not private.
cat >"$lib/pkgconfig/seiche-coupling.pc" <<EOF
prefix=$prefix
libdir=\${prefix}/lib
includedir=\${prefix}/include/seiche

Name: seiche-coupling
Description: Seiche fluid two-way coupled with Bullet rigid bodies (static; C API over Bullet)
Version: $version
Requires: seiche-fluid = $version bullet
Libs: -L\${libdir} -lseiche_coupling -lseiche_phys -lstdc++ -lm
Cflags: -I\${includedir}
EOF
echo "installed seiche $version into $dest$prefix"
