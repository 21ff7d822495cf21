#!/bin/sh
# Runs on a lent GPU machine, from the tree's root, with .gpu/ made by tools/gpu_pack.sh:
# unpacks the GL dispatch packages and the binaries, then the benchmark (64k-4M, 3 and 4
# iterations; with shader variants packed, tools/gpu_pack.sh NAME=DIR, tools/gpu_ab.sh
# instead: each variant against the tree's shaders, and a table of iteration x substep
# choices), a traced diverging run, every scene (frame 0 against llvmpipe's) and the suite
# in strict GL mode, each with its own time limit so that one call of the device tool fits
# (BUDGET seconds in all, default 530). Results go to $OUT as they come: env.txt, run.log,
# bench.tgz or ab.tgz, trace.tgz, scenes.tgz, suite.log, testlogs.tgz. tools/gpu_check.sh
# does the work; docs/performance.md, "On an NVIDIA H100", has what runs found.
cd "$(dirname "$0")/.." || exit 2
T0=$(date +%s)
el() { echo "[$(($(date +%s) - T0)) s] $*"; }
O=${OUT:-build/gpu-device}
mkdir -p "$O"
for f in .gpu/debs/*.deb; do dpkg -x "$f" /; done
ldconfig
LD_LIBRARY_PATH="$PWD/.gpu/lib"
for l in .gpu/fallback/*; do
    ldconfig -p | grep -q "[[:space:]]$(basename "$l") " || { LD_LIBRARY_PATH="$LD_LIBRARY_PATH:$PWD/.gpu/fallback"; break; }
done
export LD_LIBRARY_PATH
j=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
[ -n "${__EGL_VENDOR_LIBRARY_FILENAMES:-}" ] || [ ! -f $j ] || export __EGL_VENDOR_LIBRARY_FILENAMES=$j
mkdir -p build && rm -rf build/bin build/lib && tar xzf .gpu/bin.tgz -C build
{
    date -u; uname -a; nvidia-smi 2>&1 | head -12; head -3 /etc/os-release
    echo "LD_LIBRARY_PATH=$LD_LIBRARY_PATH EGL vendor: ${__EGL_VENDOR_LIBRARY_FILENAMES:-unset}"
    ldd build/bin/seiche | grep -E 'not found' ; nproc
} >"$O/env.txt" 2>&1
el "env"
if [ -d .gpu/variants ] && [ -n "$(ls .gpu/variants)" ]; then
    # Shader variants packed by tools/gpu_pack.sh NAME=DIR: timed against the tree's shaders
    # (4 iterations, 1 substep; AB_SIZES, AB_ROUNDS), then the tree's over iteration x
    # substep choices (QUALITY_ARGS: seiche-bench's), then with DEBUG_RUN=1 1M x 3 x 1 with
    # the driver's KHR_debug messages on (SEICHE_GL_DEBUG=1).
    set --
    for d in .gpu/variants/*; do set -- "$@" "$(basename "$d")=$d"; done
    timeout -k 5 ${AB_LIMIT:-200} tools/gpu_ab.sh --sizes ${AB_SIZES:-262144,1048576,4194304} --rounds ${AB_ROUNDS:-1} \
        --timeout 45 --out build/g-ab "$@" tree=shaders >>"$O/run.log" 2>&1
    el "variants: exit $?"
    cut -c1-100 build/g-ab/table.txt
    # Quality per millisecond: the tree's shaders over iteration x substep choices.
    # shellcheck disable=SC2086
    timeout -k 5 ${QUALITY_LIMIT:-90} build/bin/seiche-bench ${QUALITY_ARGS:---particles 1048576 --iterations 2,3 --substeps 4} \
        --steps 60 --warmup 10 --shaders shaders --json build/g-ab/quality.json >build/g-ab/quality.txt 2>&1
    el "quality: exit $?"
    grep -E '^ *[0-9]' build/g-ab/quality.txt | cut -c1-100
    if [ "${DEBUG_RUN:-0}" = 1 ]; then
        SEICHE_GL_DEBUG=1 timeout -k 5 40 build/bin/seiche-bench --particles 1048576 --iterations 3 --steps 20 --warmup 2 \
            --shaders shaders >build/g-ab/debug.txt 2>&1
        el "1M x 3 x 1 with KHR_debug: exit $?"
    fi
    tar czf "$O/ab.tgz" -C build g-ab
else
    for it in 4 3; do
        timeout -k 5 80 tools/gpu_check.sh --parts bench --bench-iterations $it --bench-steps 60 --bench-warmup 10 \
            --timeout 40 --out build/g-bench$it >>"$O/run.log" 2>&1
        el "bench, $it iterations: exit $?"
    done
    tar czf "$O/bench.tgz" -C build g-bench4 g-bench3
    grep '^| [0-9]' build/g-bench4/report.md | cut -c1-80
fi
# A dam break that diverges (1M, 2 iterations x 1 substep): with --trace, one line per step;
# its neighbour pass once grew to seconds a step (docs/performance.md, "On an NVIDIA H100").
mkdir -p build/g-trace
timeout -k 5 ${TRACE_LIMIT:-60} build/bin/seiche-bench --particles 1048576 --iterations 2 --steps 60 --warmup 10 \
    --shaders shaders --trace build/g-trace/trace_1m_2x1.csv >build/g-trace/bench.txt 2>&1
el "diverging 1M x 2 x 1, traced: exit $?"
grep -E '^ *[0-9]' build/g-trace/bench.txt | cut -c1-100
awk -F, 'NR > 1 && $7 + 0 > m { m = $7 + 0; s = $4 } END { print "slowest step on the GPU: " s ", " m " ms" }' \
    build/g-trace/trace_1m_2x1.csv 2>/dev/null
tar czf "$O/trace.tgz" -C build g-trace
timeout -k 5 120 tools/gpu_check.sh --parts scenes --frames 120 --timeout 25 --reference .gpu/ref.json \
    --out build/g-scenes >>"$O/run.log" 2>&1
el "scenes: exit $?"
tar czf "$O/scenes.tgz" -C build g-scenes
grep '^| ' build/g-scenes/report.md | cut -c1-120
left=$((${BUDGET:-530} - ($(date +%s) - T0)))
SEICHE_FUZZ_SECONDS=0 timeout -k 5 "$left" tests/run.sh >"$O/suite.log" 2>&1
el "suite ($left s allowed): exit $?"
tar czf "$O/testlogs.tgz" -C build test-logs
grep -E '^FAILED|passed,' "$O/suite.log"
