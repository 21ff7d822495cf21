#!/bin/sh
# Packs what a lent GPU machine needs to run the suite, the scenes and the benchmark
# (../shared/GPU.md, docs/performance.md "Running the GPU check") into .gpu/ (git-ignored
# through .git/info/exclude, which this adds): the binaries of build/bin stripped, with the
# static libraries test_relocatable reads and build/lib, as .gpu/bin.tgz; every library they
# load outside libc and the GL drivers in .gpu/lib (libstdc++, libgcc_s and zlib in
# .gpu/fallback, used only where the machine has none); Debian's GL dispatch packages in
# .gpu/debs; and an llvmpipe reference of each scene's frame-0 density in .gpu/ref.json.
# Then, through the device tool: run `sh tools/gpu_device.sh` with carry [".gpu"].
# Build first (make build). About 30 MB.
# Arguments NAME=DIR (optional): shader trees to time against the tree's own shaders on the
# device (tools/gpu_ab.sh), copied to .gpu/variants/NAME; e.g. the shaders of an earlier
# commit: git archive HEAD~1 shaders | tar -x -C /tmp/old, then old=/tmp/old/shaders.
set -e
cd "$(dirname "$0")/.."
[ -x build/bin/seiche ] || { echo "gpu_pack: build first (make build)" >&2; exit 2; }
grep -qx '/.gpu/' .git/info/exclude 2>/dev/null || echo '/.gpu/' >>.git/info/exclude
rm -rf .gpu && mkdir -p .gpu/lib .gpu/fallback .gpu/debs
tmp=$(mktemp -d)
mkdir -p "$tmp/bin" "$tmp/lib"
cp build/bin/seiche build/bin/seiche-* build/bin/test_* "$tmp/bin/"
cp build/bin/libseiche_fluid.a build/bin/libseiche_engine.a "$tmp/bin/"
strip "$tmp"/bin/seiche* "$tmp"/bin/test_*
strip -g "$tmp"/bin/*.a
cp -a build/lib/. "$tmp/lib/"
tar czf .gpu/bin.tgz -C "$tmp" bin lib
rm -rf "$tmp"
for b in build/bin/seiche build/bin/seiche-* build/bin/test_*; do ldd "$b"; done | awk '$3 ~ /^\// { print $3 }' | sort -u |
    grep -Ev 'libc\.so|libm\.so|libdl\.so|libpthread|ld-linux|librt\.so|libGL|libEGL|libOpenGL|libGLX|libgbm|libdrm|libglapi' |
    while read -r l; do
        case $l in
        *libstdc++* | *libgcc_s* | *libz.so*) cp -L "$l" .gpu/fallback/ ;;
        *) cp -L "$l" .gpu/lib/ ;;
        esac
    done
(cd .gpu/debs && apt-get download libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2 >/dev/null 2>&1) ||
    echo "gpu_pack: apt-get download of the GL dispatch packages failed: .gpu/debs is empty" >&2
for v in "$@"; do
    case $v in *=*) ;; *) echo "gpu_pack: a variant is NAME=DIR (got '$v')" >&2; exit 2 ;; esac
    [ -f "${v#*=}/fluid/common.glsl" ] || { echo "gpu_pack: ${v#*=} is not a shader tree" >&2; exit 2; }
    mkdir -p ".gpu/variants/${v%%=*}"
    cp -r "${v#*=}/." ".gpu/variants/${v%%=*}/"
done
tools/gpu_check.sh --parts scenes --frames 2 --out build/gpu-ref >/dev/null 2>&1 || true
cp build/gpu-ref/report.json .gpu/ref.json
echo "gpu_pack: .gpu/ ready ($(du -sh .gpu | cut -f1)); on the device: sh tools/gpu_device.sh (carry .gpu)"
