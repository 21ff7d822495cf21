#!/bin/sh
# Runs libFuzzer harnesses (make fuzz; docs/testing.md).
# usage: tests/fuzz/run.sh SECONDS NAME... [-- LIBFUZZER_ARGS...]
# Each NAME (build/fuzz/bin/NAME) first replays every input of tests/fuzz/regressions/NAME/
# (the crashes found so far: each must pass now), then fuzzes for SECONDS with its corpus in
# build/fuzz/corpus/NAME (kept between runs; tests/fuzz/seeds/NAME, where there is one, adds
# starting inputs that are read, never written). A crash, leak, timeout (FUZZ_TIMEOUT seconds
# for one input, default 20) or memory blow-up (FUZZ_RSS_MB, default 2048) stops it with
# the input in build/fuzz/artifacts/NAME/. Exit status 1 when any harness failed.
cd "$(dirname "$0")/../.." || exit 2
seconds=${1:-60}
shift
names=""
while [ $# -gt 0 ] && [ "$1" != "--" ]; do
    names="$names $1"
    shift
done
[ "${1:-}" != "--" ] || shift
status=0
for name in $names; do
    exe=build/fuzz/bin/$name
    if [ ! -x "$exe" ]; then
        echo "fuzz: no $exe (make fuzz-build needs clang-14)" >&2
        status=1
        continue
    fi
    corpus=build/fuzz/corpus/$name
    artifacts=build/fuzz/artifacts/$name
    mkdir -p "$corpus" "$artifacts"
    opts="-timeout=${FUZZ_TIMEOUT:-20} -rss_limit_mb=${FUZZ_RSS_MB:-2048} -artifact_prefix=$artifacts/"
    regressions=$(ls tests/fuzz/regressions/"$name"/* 2>/dev/null)
    if [ -n "$regressions" ]; then
        # shellcheck disable=SC2086
        if ! "$exe" $opts "$@" $regressions >"build/fuzz/$name.replay.log" 2>&1; then
            echo "fuzz: $name: a regression input fails again: see build/fuzz/$name.replay.log"
            status=1
            continue
        fi
        echo "fuzz: $name: $(echo "$regressions" | wc -l) regression inputs pass"
    fi
    echo "fuzz: $name for ${seconds}s (corpus $corpus)"
    seeds=""
    [ ! -d "tests/fuzz/seeds/$name" ] || seeds="tests/fuzz/seeds/$name"
    # shellcheck disable=SC2086
    if "$exe" $opts -max_total_time="$seconds" -print_final_stats=1 "$@" "$corpus" $seeds >"build/fuzz/$name.log" 2>&1; then
        echo "fuzz: $name: ok, $(sed -n 's/^stat::number_of_executed_units: *//p' "build/fuzz/$name.log") inputs"
    else
        echo "fuzz: $name FAILED: see build/fuzz/$name.log; the input is in $artifacts/"
        grep -E 'ERROR|runtime error|SUMMARY|^    #[0-9] ' "build/fuzz/$name.log" | head -12 | sed 's/^/    /'
        status=1
    fi
done
exit $status
