#!/bin/sh
# Runs on a lent GPU machine, from the tree's root, with .gpu/ made by tools/gpu_pack.sh:
# unpacks the GL dispatch packages and the binaries, then the benchmark (64k-4M, 3 and 4
# iterations; with shader variants packed, tools/gpu_pack.sh NAME=DIR, tools/gpu_ab.sh
# instead: each variant against the tree's shaders, and a table of iteration x substep
# choices), a traced diverging run, every scene (frame 0 against llvmpipe's) and the suite
# in strict GL mode, each with its own time limit so that one call of the device tool fits
# (BUDGET seconds in all, default 530; TESTS="test_x ..." runs those programs instead of the
# suite). Results go to $OUT as they come: env.txt, run.log,
# bench.tgz or ab.tgz, extra.tgz (GRID_CELLS, PEER, RENDER: see below), trace.tgz,
# scenes.tgz, suite.log, testlogs.tgz. tools/gpu_check.sh
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
    # Quality per millisecond: the tree's shaders over iteration x substep choices
    # (QUALITY_LIMIT=0 skips it).
    if [ "${QUALITY_LIMIT:-90}" -gt 0 ]; then
        # shellcheck disable=SC2086
        timeout -k 5 ${QUALITY_LIMIT:-90} build/bin/seiche-bench ${QUALITY_ARGS:---particles 1048576 --iterations 2,3 --substeps 4} \
            --steps 60 --warmup 10 --shaders shaders --json build/g-ab/quality.json >build/g-ab/quality.txt 2>&1
        el "quality: exit $?"
        grep -E '^ *[0-9]' build/g-ab/quality.txt | cut -c1-100
    fi
    # TANK_TEST=N: each variant and the tree at N particles in the benchmark's tank and in one
    # 20 times wider and deeper (seiche-bench --tank-test: the ratios of time and memory).
    if [ -n "${TANK_TEST:-}" ]; then
        for d in .gpu/variants/* shaders; do
            timeout -k 5 60 build/bin/seiche-bench --particles "$TANK_TEST" --iterations 4 --steps 60 --warmup 10 \
                --tank-test --shaders "$d" >"build/g-ab/tank-$(basename "$(dirname "$d")")-$(basename "$d").txt" 2>&1
            echo "$d: $(grep -E 'wider and deeper' "build/g-ab/tank-$(basename "$(dirname "$d")")-$(basename "$d").txt" | cut -c1-120)"
        done
        el "tank test: done"
    fi
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
# Optional extras, each in build/g-extra (extra.tgz), each under its own time limit:
# GRID_CELLS="1 3": 1M x 4 x 1 with those grid cells per kernel radius (the default, 2, is the
# tree's row of the benchmark or variants above); PEER=1 with .gpu/peer/run_peer.sh (a peer's benchmark, packed by hand):
# the peer and seiche-bench in turn, PEER_ROUNDS rounds, at PEER_SIZES and PEER_ITERATIONS
# (run_peer.sh reads PARTICLES, ITERATIONS, SMOKE, VARIANTS, CASE_TIMEOUT from the environment
# and prints lines that start with "peer "; PEER_VARIANTS: its VARIANTS, in the first run only); binary variants
# in .gpu/bins (below); RENDER=1:
# seiche-render-bench at 1M, the surface look and spheres, raster and compute splats, and
# seiche-bench --render surface (frames per second, the step and drawing; 4 x 1 both ways, then
# the defaults' 2 x 4 with compute splats); DEBUG_SCENE=1: floating_objects
# with the driver's KHR_debug messages (SEICHE_GL_DEBUG=1). EXTRA_SIZE (default 1048576)
# replaces 1M in the first and the last.
mkdir -p build/g-extra
es=${EXTRA_SIZE:-1048576}
if [ -n "${GRID_CELLS:-}" ]; then
    for k in $GRID_CELLS; do
        timeout -k 5 45 build/bin/seiche-bench --particles "$es" --iterations 4 --steps 60 --warmup 10 \
            --shaders shaders --grid-cells "$k" >build/g-extra/grid-$k.txt 2>&1
        echo "grid cells $k: $(grep -E '^ *[0-9]' build/g-extra/grid-$k.txt | tail -n 1 | cut -c1-90)"
    done
    el "grid cells: done"
fi
if [ -d .gpu/bins ] && [ -n "$(ls .gpu/bins)" ]; then
    # Binary variants (packed by hand: .gpu/bins/NAME/seiche-bench and NAME/shaders, for a
    # change of the passes' contract that a shader tree alone cannot carry), at AB_SIZES, 4
    # iterations x 1 substep, to compare with the tree's rows above.
    for n in $(echo "${AB_SIZES:-262144,1048576,4194304}" | tr ',' ' '); do
        for d in .gpu/bins/*; do
            b=$d/seiche-bench s=$d/shaders
            timeout -k 5 45 "$b" --particles "$n" --iterations 4 --steps 60 --warmup 10 --shaders "$s" \
                >"build/g-extra/bin-$(basename "$d")-$n.txt" 2>&1
            echo "$(basename "$d") $n: $(grep -E '^ *[0-9]' "build/g-extra/bin-$(basename "$d")-$n.txt" | tail -n 1 | cut -c1-100)"
        done
    done
    el "binary variants: done"
fi
if [ "${PEER:-0}" = 1 ] && [ -f .gpu/peer/run_peer.sh ]; then
    r=1 smoke=1
    while [ "$r" -le "${PEER_ROUNDS:-2}" ]; do
        for n in $(echo "${PEER_SIZES:-1030301}" | tr ',' ' '); do
            for k in $(echo "${PEER_ITERATIONS:-4}" | tr ',' ' '); do
                timeout -k 5 60 build/bin/seiche-bench --particles "$n" --iterations "$k" --steps 60 --warmup 10 \
                    --shaders shaders >"build/g-extra/seiche-$n-$k-$r.txt" 2>&1
                echo "seiche $n x $k round $r: $(grep -E '^ *[0-9]' "build/g-extra/seiche-$n-$k-$r.txt" | tail -n 1 | cut -c1-100)"
                PARTICLES=$n ITERATIONS=$k SMOKE=$smoke VARIANTS=${PEER_VARIANTS:-} \
                    CASE_TIMEOUT=45 timeout -k 5 150 sh .gpu/peer/run_peer.sh >"build/g-extra/peer-$n-$k-$r.txt" 2>&1
                echo "peer $n x $k round $r: exit $?"
                grep -E '^peer ' "build/g-extra/peer-$n-$k-$r.txt" | cut -c1-200
                PEER_VARIANTS="" smoke=0
            done
        done
        r=$((r + 1))
    done
    el "peer: done"
fi
if [ "${RENDER:-0}" = 1 ]; then
    # Each pass, raster then compute splats (the render bench's default); then whole frames:
    # the issue's step (4 iterations x 1 substep, dt 4 ms) and the surface drawn every step,
    # both ways, in turn.
    timeout -k 5 90 build/bin/seiche-render-bench --particles "$es" --frames 60 --warmup 10 --mode surface,spheres \
        --shaders shaders >build/g-extra/render.txt 2>&1
    el "render $es: exit $?"
    grep -iE 'ms|frame|splat' build/g-extra/render.txt | cut -c1-120
    for sp in raster compute raster compute; do
        timeout -k 5 60 build/bin/seiche-bench --particles "$es" --iterations 4 --steps 60 --warmup 10 \
            --shaders shaders --render surface --splat "$sp" >"build/g-extra/frames-$sp.txt" 2>&1
        echo "frames, $sp splats: $(grep -E '^ *[0-9]' "build/g-extra/frames-$sp.txt" | tail -n 1 | sed 's/.*frame_ms/frame_ms/')"
    done
    # The same at the defaults' solve (2 iterations x 4 substeps), compute splats.
    timeout -k 5 60 build/bin/seiche-bench --particles "$es" --iterations 2 --substeps 4 --steps 60 --warmup 10 \
        --shaders shaders --render surface --splat compute >build/g-extra/frames-defaults.txt 2>&1
    echo "frames, 2 x 4, compute splats: $(grep -E '^ *[0-9]' build/g-extra/frames-defaults.txt | tail -n 1 | cut -c1-60) ... $(grep -E '^ *[0-9]' build/g-extra/frames-defaults.txt | tail -n 1 | sed 's/.*frame_ms/frame_ms/')"
    el "frames: done"
fi
if [ "${DEBUG_SCENE:-0}" = 1 ]; then
    # The driver's KHR_debug messages in a scene with bodies (buffers moved to host memory).
    SEICHE_GL_DEBUG=1 timeout -k 5 40 build/bin/seiche --headless --frames 120 --shaders shaders \
        scripts/scenes/floating_objects.lua >build/g-extra/debug_floating.txt 2>&1
    el "floating_objects with KHR_debug: exit $?"
    grep -ciE 'memory|performance' build/g-extra/debug_floating.txt
fi
tar czf "$O/extra.tgz" -C build g-extra
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
timeout -k 5 ${SCENES_LIMIT:-120} tools/gpu_check.sh --parts scenes --frames 120 --timeout 25 --reference .gpu/ref.json \
    --out build/g-scenes >>"$O/run.log" 2>&1
el "scenes: exit $?"
tar czf "$O/scenes.tgz" -C build g-scenes
grep '^| ' build/g-scenes/report.md | cut -c1-120
left=$((${BUDGET:-530} - ($(date +%s) - T0)))
if [ -n "${TESTS:-}" ]; then
    # Only these test programs (TESTS="test_a test_b"), not the suite.
    for t in $TESTS; do
        SEICHE_GL_STRICT=${SEICHE_GL_STRICT:-1} SEICHE_TEST_VERBOSE=1 timeout -k 5 "$left" "build/bin/$t" >"$O/$t.log" 2>&1
        el "$t: exit $?"
        grep -E '^\[  (PASSED|FAILED) ' "$O/$t.log"
    done
else
    SEICHE_FUZZ_SECONDS=0 timeout -k 5 "$left" tests/run.sh >"$O/suite.log" 2>&1
    el "suite ($left s allowed): exit $?"
    tar czf "$O/testlogs.tgz" -C build test-logs
    grep -E '^FAILED|passed,' "$O/suite.log"
fi
