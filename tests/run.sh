#!/bin/sh
# Runs the whole test suite: every cmocka program (build/bin/test_*), then every script
# test (tests/scripts/*.lua) through `seiche --headless`. A script test passes when the
# runner's exit status matches the one its first lines declare (`-- expect-exit: N`,
# default 0) and, if declared, stderr contains `-- expect-stderr: TEXT` (repeatable).
# `-- frames: N` and `-- budget: SECONDS` (the callback time budget) pass to the runner;
# `-- trusted: WHY` runs it with --trusted (every standard library: for tests that run a
# shipped scene with dofile and add checks, docs/runner.md).
# `-- needs: PROGRAM` (repeatable) skips the script when PROGRAM is not on the PATH.
# `-- unsanitized: WHY` skips it in the sanitizer build's run (SEICHE_SANITIZER_REPORTS set),
# e.g. a script whose importer must fail an allocation (AddressSanitizer reports one).
# A cmocka test may skip itself (cmocka's skip(), with the reason printed first as a line
# "SKIPPED: ..."), e.g. one that needs Mesa on another driver: it counts as skipped.
# Then each libFuzzer harness of tests/fuzz/ for a few seconds (SEICHE_FUZZ_SECONDS).
# Prints one line per test program / script and ends with "N passed, N failed, N skipped".
#
# SEICHE_BIN=DIR runs the programs of another build (default build/bin), e.g. the sanitizer
# build's build/sanitize/bin (make sanitize, through tests/sanitize.sh). When
# SEICHE_SANITIZER_REPORTS names a directory (the log_path of ASAN_OPTIONS/UBSAN_OPTIONS),
# a sanitizer report written there while a test ran fails that test, children included.
cd "$(dirname "$0")/.." || exit 2
bin=${SEICHE_BIN:-build/bin}
reports=${SEICHE_SANITIZER_REPORTS:-}
# The strict GL mode (docs/runner.md) is on unless the caller sets SEICHE_GL_STRICT=0: a
# missing barrier or a clear-then-upload stops the test that hit it with exit status 5.
SEICHE_GL_STRICT=${SEICHE_GL_STRICT:-1}
export SEICHE_GL_STRICT
echo "SEICHE_GL_STRICT=$SEICHE_GL_STRICT"
passed=0
failed=0
skipped=0
failures=""
log_dir=${SEICHE_TEST_LOGS:-build/test-logs}
mkdir -p "$log_dir"
[ -z "$reports" ] || mkdir -p "$reports"

# sanitizer_reports NAME: 0 when no sanitizer report appeared since the last call; else
# moves them to $log_dir/NAME.sanitizer, prints their first lines and returns 1.
sanitizer_reports() {
    [ -n "$reports" ] || return 0
    set -- "$1" "$reports"/*
    [ -e "$2" ] || return 0
    report_file="$log_dir/$1.sanitizer"
    shift
    cat "$@" >"$report_file"
    rm -f "$@"
    echo "    sanitizer report ($report_file):"
    grep -E 'ERROR|runtime error|SUMMARY|^    #[0-9] ' "$report_file" | head -12 | sed 's/^/    /'
    return 1
}

for t in "$bin"/test_*; do
    [ -x "$t" ] || continue
    name=$(basename "$t")
    start=$(date +%s)
    if "$t" >"$log_dir/$name.log" 2>&1; then status=ok; else status=FAILED; fi
    secs=$(( $(date +%s) - start ))
    sanitizer_reports "$name" >"$log_dir/$name.sanitizer-summary" || {
        status=FAILED
        echo "[  FAILED  ] 1 test(s): a sanitizer report (see $name.sanitizer)" >>"$log_dir/$name.log"
    }
    n_pass=$(sed -n 's/^\[  PASSED  \] \([0-9]*\) test.*/\1/p' "$log_dir/$name.log" | awk '{s+=$1} END {print s+0}')
    n_fail=$(sed -n 's/^\[  FAILED  \] \([0-9]*\) test.*/\1/p' "$log_dir/$name.log" | awk '{s+=$1} END {print s+0}')
    n_skip=$(sed -n 's/^\[  SKIPPED \] \([0-9]*\) test.*/\1/p' "$log_dir/$name.log" | awk '{s+=$1} END {print s+0}')
    skipped=$((skipped + n_skip))
    if [ "$status" = ok ]; then
        passed=$((passed + n_pass))
        [ $((n_pass + n_skip)) -gt 0 ] || passed=$((passed + 1))
        if [ "$n_skip" -gt 0 ]; then
            echo "ok      $name ($n_pass tests, $n_skip skipped, ${secs}s)"
        else
            echo "ok      $name ($n_pass tests, ${secs}s)"
        fi
    else
        failed=$((failed + (n_fail > 0 ? n_fail : 1)))
        passed=$((passed + n_pass))
        failures="$failures $name"
        echo "FAILED  $name ($n_pass passed, $n_fail failed, ${secs}s): see $log_dir/$name.log"
        sed 's/^/    /' "$log_dir/$name.log" | grep -E 'FAIL|ERROR|error|Assert|assert' | head -20
        cat "$log_dir/$name.sanitizer-summary"
    fi
    rm -f "$log_dir/$name.sanitizer-summary"
    # Each skipped test with the reason it printed just before skipping.
    [ "$n_skip" = 0 ] || awk '/^SKIPPED: / { why = substr($0, 10) }
        /^\[  SKIPPED \] / && !/ test\(s\)/ && why != "" { print "    skipped " $4 ": " why; why = "" }' "$log_dir/$name.log"
done

# verdict OK KIND NAME PASS_TEXT FAIL_TEXT SECONDS: counts and prints one runner-driven test,
# with the first lines of its stderr ($log_dir/KIND_NAME.err) when it failed.
verdict() {
    if [ "$1" = 1 ]; then
        passed=$((passed + 1))
        echo "ok      $2 $3 ($4, ${6}s)"
    else
        failed=$((failed + 1))
        failures="$failures $2:$3"
        echo "FAILED  $2 $3: $5, ${6}s; stderr:"
        sed 's/^/    /' "$log_dir/$2_$3.err" | head -20
    fi
}

for s in tests/scripts/*.lua; do
    [ -f "$s" ] || continue
    name=$(basename "$s" .lua)
    expect=$(sed -n 's/^-- expect-exit: *\([0-9]*\).*/\1/p' "$s" | head -n 1)
    [ -n "$expect" ] || expect=0
    frames=$(sed -n 's/^-- frames: *\([0-9]*\).*/\1/p' "$s" | head -n 1)
    [ -n "$frames" ] || frames=600
    budget=$(sed -n 's/^-- budget: *\([0-9.]*\).*/\1/p' "$s" | head -n 1)
    budget_opt=""
    [ -z "$budget" ] || budget_opt="--budget $budget"
    ! grep -q '^-- trusted:' "$s" || budget_opt="$budget_opt --trusted"
    missing=""
    for prog in $(sed -n 's/^-- needs: *//p' "$s"); do
        command -v "$prog" >/dev/null 2>&1 || missing="$missing $prog"
    done
    if [ -n "$missing" ]; then
        skipped=$((skipped + 1))
        echo "skipped script $name: needs$missing on the PATH"
        continue
    fi
    if [ -n "$reports" ] && grep -q '^-- unsanitized:' "$s"; then
        skipped=$((skipped + 1))
        echo "skipped script $name: $(sed -n 's/^-- unsanitized: *//p' "$s" | head -n 1)"
        continue
    fi
    start=$(date +%s)
    # shellcheck disable=SC2086
    "$bin"/seiche --headless --quiet --frames "$frames" $budget_opt "$s" >"$log_dir/script_$name.out" 2>"$log_dir/script_$name.err"
    rc=$?
    secs=$(( $(date +%s) - start ))
    ok=1
    [ "$rc" = "$expect" ] || ok=0
    sanitizer_reports "script_$name" >>"$log_dir/script_$name.err" || ok=0
    # Each expected stderr text must appear.
    while IFS= read -r want; do
        [ -n "$want" ] || continue
        grep -qF -- "$want" "$log_dir/script_$name.err" || ok=0
    done <<EOT
$(sed -n 's/^-- expect-stderr: *//p' "$s")
EOT
    verdict "$ok" script "$name" "exit $rc" "exit $rc (expected $expect)" "$secs"
done

# Every shipped scene, as a user would start it, for 60 frames (exit 0 expected).
for s in scripts/scenes/*.lua; do
    [ -f "$s" ] || continue
    name=$(basename "$s" .lua)
    start=$(date +%s)
    "$bin"/seiche --headless --quiet --frames 60 "$s" >"$log_dir/scene_$name.out" 2>"$log_dir/scene_$name.err"
    rc=$?
    secs=$(( $(date +%s) - start ))
    ok=0
    [ "$rc" != 0 ] || ok=1
    sanitizer_reports "scene_$name" >>"$log_dir/scene_$name.err" || ok=0
    verdict "$ok" scene "$name" "exit 0" "exit $rc" "$secs"
done

# The benchmarks run and print what they are for (tiny sizes: a smoke test, not a timing):
# seiche-bench drawing every step (frames per second), seiche-render-bench with both
# splats, and a bad option refused naming it (exit 2).
bench_case() { # NAME EXPECTED_EXIT TEXT COMMAND...
    name=$1 expect=$2 want=$3
    shift 3
    start=$(date +%s)
    "$@" >"$log_dir/bench_$name.err" 2>&1
    rc=$?
    secs=$(( $(date +%s) - start ))
    ok=1
    [ "$rc" = "$expect" ] || ok=0
    grep -qF -- "$want" "$log_dir/bench_$name.err" || ok=0
    sanitizer_reports "bench_$name" >>"$log_dir/bench_$name.err" || ok=0
    verdict "$ok" bench "$name" "exit $rc, '$want'" "exit $rc (expected $expect), or no '$want'" "$secs"
}
bench_case frames_per_second 0 "frames/s" "$bin"/seiche-bench --particles 2000 --steps 3 --warmup 1 \
    --render surface --size 96x64
bench_case render_both_splats 0 "surface (splat compute)" "$bin"/seiche-render-bench --particles 2000 --frames 2 \
    --warmup 1 --size 96x64 --mode surface
bench_case bad_splat 2 "--splat must be raster or compute (got 'vulkan')" "$bin"/seiche-bench --particles 2000 \
    --render surface --splat vulkan

# Every libFuzzer harness of tests/fuzz/ (built by make fuzz-build with clang-14): the inputs
# of tests/fuzz/regressions/NAME/ replayed, then SEICHE_FUZZ_SECONDS (default 10; 0 skips)
# of fuzzing from the corpus in build/fuzz/corpus/NAME (tests/fuzz/run.sh). Skipped when
# the harness is not built.
fuzz_seconds=${SEICHE_FUZZ_SECONDS:-10}
for f in tests/fuzz/fuzz_*.c; do
    [ -f "$f" ] || continue
    name=$(basename "$f" .c)
    if [ ! -x "build/fuzz/bin/$name" ] || [ "$fuzz_seconds" = 0 ]; then
        skipped=$((skipped + 1))
        if [ "$fuzz_seconds" = 0 ]; then echo "skipped fuzz $name: SEICHE_FUZZ_SECONDS=0"
        else echo "skipped fuzz $name: not built (make fuzz-build, which needs clang-14)"; fi
        continue
    fi
    start=$(date +%s)
    tests/fuzz/run.sh "$fuzz_seconds" "$name" >"$log_dir/fuzz_$name.err" 2>&1
    rc=$?
    secs=$(( $(date +%s) - start ))
    ok=1
    [ "$rc" = 0 ] || ok=0
    sanitizer_reports "fuzz_$name" >>"$log_dir/fuzz_$name.err" || ok=0
    inputs=$(sed -n 's/^fuzz: .*: ok, \([0-9]*\) inputs$/\1/p' "$log_dir/fuzz_$name.err")
    verdict "$ok" fuzz "$name" "${inputs:-?} inputs, regressions replayed" "exit $rc" "$secs"
done

echo
[ -z "$failures" ] || echo "failed:$failures"
echo "$passed passed, $failed failed, $skipped skipped"
[ "$failed" = 0 ]
