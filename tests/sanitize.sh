#!/bin/sh
# The whole suite (tests/run.sh) against the sanitizer build in build/sanitize/bin
# (make sanitize builds it first). Every program, and every child it starts, runs with:
#   ASan:  halt_on_error=1, leaks detected at exit (LeakSanitizer) with the suppressions of
#          tests/sanitize/lsan.supp (allocations inside Mesa, LLVM, EGL and libepoxy only;
#          never our code), exit status 97 on a report (no test expects it);
#   UBSan: halt_on_error=1, print_stacktrace=1, the same exit status;
# and reports go to files under build/test-logs/sanitizer/, where tests/run.sh finds them and
# fails the test that wrote one (children whose status a test does not look at included).
# Extra options: set ASAN_OPTIONS / UBSAN_OPTIONS / LSAN_OPTIONS; ours come after them and
# win. docs/testing.md has the details.
cd "$(dirname "$0")/.." || exit 2
root=$(pwd)
bin=${SEICHE_BIN:-build/sanitize/bin}
if [ ! -x "$bin/seiche" ]; then
    echo "sanitize: no $bin/seiche: build it first (make sanitize-build)" >&2
    exit 2
fi
# Mesa's EGL unloads the llvmpipe driver (swrast_dri.so) before LeakSanitizer looks: what
# the driver still holds in its globals then looks leaked, from "<unknown module>", and
# cannot be suppressed by name. Preloading the driver keeps it loaded to the end (its memory
# stays reachable, its frames keep their names); ASan must then allow a library ahead of it.
# SEICHE_SANITIZE_DRIVER=PATH names another driver, "" none.
multiarch=$(gcc -print-multiarch 2>/dev/null || echo x86_64-linux-gnu)
driver=${SEICHE_SANITIZE_DRIVER-/usr/lib/$multiarch/dri/swrast_dri.so}
if [ -n "$driver" ] && [ -f "$driver" ]; then
    LD_PRELOAD="$driver${LD_PRELOAD:+ $LD_PRELOAD}"
    export LD_PRELOAD
    link_order=":verify_asan_link_order=0"
else
    echo "sanitize: no GL driver to preload ($driver): leaks inside it may be reported" >&2
    link_order=""
fi
reports="$root/build/test-logs/sanitizer"
rm -rf "$reports"
mkdir -p "$reports"
common="halt_on_error=1:exitcode=97:log_path=$reports/report:print_summary=1"
ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}$common:detect_leaks=1:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=0:check_initialization_order=1$link_order"
LSAN_OPTIONS="${LSAN_OPTIONS:+$LSAN_OPTIONS:}suppressions=$root/tests/sanitize/lsan.supp:print_suppressions=0"
UBSAN_OPTIONS="${UBSAN_OPTIONS:+$UBSAN_OPTIONS:}$common:print_stacktrace=1"
SEICHE_BIN=$bin
SEICHE_SANITIZER_REPORTS=$reports
export ASAN_OPTIONS LSAN_OPTIONS UBSAN_OPTIONS SEICHE_BIN SEICHE_SANITIZER_REPORTS
echo "sanitize: $bin; ASAN_OPTIONS=$ASAN_OPTIONS"
echo "sanitize: UBSAN_OPTIONS=$UBSAN_OPTIONS"
[ -z "${LD_PRELOAD:-}" ] || echo "sanitize: LD_PRELOAD=$LD_PRELOAD"
start=$(date +%s)
tests/run.sh
rc=$?
echo "sanitize: the suite took $(( $(date +%s) - start )) s"
exit $rc
