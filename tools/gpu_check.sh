#!/bin/sh
# shellcheck disable=SC2015 # the "check && check || die" lines: die exits
# One command for a GPU check (issue 9, ../shared/GPU.md): on whatever OpenGL the machine
# has, runs the test suite, every scene headless with --metrics, and the benchmark, and
# writes one report, Markdown and JSON, headed by the date, the GL renderer and the driver
# version (GL_VERSION). Keeps going when a part fails, records it, and exits 1 when the
# suite, a scene or a benchmark run failed (2: bad usage). Needs only sh, awk, sed and
# coreutils besides the binaries; `tools/gpu_check.sh --help` for the options.
usage() {
    cat <<'EOF'
usage: tools/gpu_check.sh [options]
Runs, on the OpenGL at hand: the test suite (tests/run.sh), every scene for --frames
frames headless with --metrics and a screenshot, and seiche-bench at each size; writes
OUT/report.md and OUT/report.json (rewritten after each part, so a run cut short leaves
what it had), with the logs, metrics CSVs, screenshots and benchmark JSON beside them.

  --bin DIR            the binaries: seiche, seiche-bench, test_* (default: build/bin of
                       the tree this script is in). The suite always runs the tree's
                       tests/run.sh, which uses the tree's build/bin.
  --out DIR            where the report goes (default: build/gpu-check)
  --scenes DIR         the scene scripts, every *.lua in it (default: scripts/scenes)
  --frames N           frames per scene (default: 240)
  --size WxH           framebuffer size of the scenes (default: the runner's, 1280x720)
  --bench-sizes LIST   particle counts, comma-separated, one benchmark run each
                       (default: 64000,262144,1048576,4194304)
  --bench-steps M      measured steps per size (default: 60)
  --bench-warmup W     warm-up steps per size (default: 10)
  --bench-iterations K solver iterations in the benchmark (default: 3)
  --shaders DIR        read shaders from DIR in the runner and the benchmark (default:
                       $SEICHE_SHADER_DIR if set, else none: the shaders built into the
                       binaries, which is what a user runs)
  --parts LIST         which parts to run, comma-separated: suite, scenes, bench
                       (default: suite,scenes,bench)
  --reference FILE     a report.json from another machine (e.g. llvmpipe): each scene's
                       frame-0 rho_max is compared with it and a difference over
                       --tolerance fails the scene
  --tolerance PERCENT  for --reference (default: 5)
  --timeout SECONDS    longest one scene or one benchmark size may run (default: 300);
                       the suite gets four times as long. Needs coreutils' timeout.
  --help               this text

A scene fails when the runner exits non-zero, writes no metrics, reports a NaN, or
(with --reference) its frame-0 rho_max differs by more than the tolerance. Exit status:
0 when everything that ran passed, 1 when the suite, a scene or a benchmark size failed,
2 for a usage error.

Examples:
  tools/gpu_check.sh                                     # the full check (a GPU)
  tools/gpu_check.sh --frames 30 --bench-sizes 4000,16000 --bench-steps 10 \
      --out build/gpu-check-llvmpipe                     # a quick one on llvmpipe
  tools/gpu_check.sh --reference build/gpu-check-llvmpipe/report.json
See docs/performance.md ("Running the GPU check") and ../shared/GPU.md.
EOF
}

die() { echo "gpu_check: $*" >&2; exit 2; }

here=$(cd "$(dirname "$0")" && pwd) || exit 2
root=$(cd "$here/.." && pwd) || exit 2

bin="$root/build/bin"
out="$root/build/gpu-check"
scenes_dir="$root/scripts/scenes"
frames=240
size=""
bench_sizes="64000,262144,1048576,4194304"
bench_steps=60
bench_warmup=10
bench_iterations=3
shaders=""
parts="suite,scenes,bench"
reference=""
tolerance=5
limit=300

is_uint() { case "$1" in '' | *[!0-9]*) return 1 ;; *) return 0 ;; esac; }

while [ $# -gt 0 ]; do
    opt=$1
    case "$opt" in
    --help | -h) usage; exit 0 ;;
    --bin | --out | --scenes | --frames | --size | --bench-sizes | --bench-steps | --bench-warmup | \
        --bench-iterations | --shaders | --parts | --reference | --tolerance | --timeout)
        [ $# -ge 2 ] || die "$opt needs a value"
        val=$2
        shift 2
        ;;
    *) usage >&2; die "unknown option '$opt'" ;;
    esac
    case "$opt" in
    --bin) bin=$val ;;
    --out) out=$val ;;
    --scenes) scenes_dir=$val ;;
    --frames) is_uint "$val" && [ "$val" -gt 0 ] || die "--frames must be a whole number > 0 (got '$val')"; frames=$val ;;
    --size) case "$val" in *[!0-9x]* | x* | *x | '') die "--size must be WxH (got '$val')" ;; esac; size=$val ;;
    --bench-sizes)
        case "$val" in '' | ,* | *, | *,,* | *[!0-9,]*) die "--bench-sizes must be whole numbers separated by commas (got '$val')" ;; esac
        bench_sizes=$val ;;
    --bench-steps) is_uint "$val" && [ "$val" -gt 0 ] || die "--bench-steps must be a whole number > 0 (got '$val')"; bench_steps=$val ;;
    --bench-warmup) is_uint "$val" || die "--bench-warmup must be a whole number (got '$val')"; bench_warmup=$val ;;
    --bench-iterations) is_uint "$val" && [ "$val" -gt 0 ] || die "--bench-iterations must be a whole number > 0 (got '$val')"; bench_iterations=$val ;;
    --shaders) shaders=$val ;;
    --parts)
        for p in $(echo "$val" | tr ',' ' '); do
            case "$p" in suite | scenes | bench) ;; *) die "--parts takes suite, scenes, bench (got '$p')" ;; esac
        done
        parts=$val ;;
    --reference) [ -f "$val" ] || die "--reference: no file '$val'"; reference=$val ;;
    --tolerance) echo "$val" | grep -Eq '^[0-9]+([.][0-9]+)?$' || die "--tolerance must be a number of percent (got '$val')"; tolerance=$val ;;
    --timeout) is_uint "$val" && [ "$val" -gt 0 ] || die "--timeout must be whole seconds > 0 (got '$val')"; limit=$val ;;
    esac
done

[ -d "$bin" ] || die "no binaries directory '$bin' (build first: make build, or pass --bin DIR)"
bin=$(cd "$bin" && pwd)
[ -z "$reference" ] || reference=$(cd "$(dirname "$reference")" && pwd)/$(basename "$reference")
case "$shaders" in
none) shaders="" ;;
"")
    if [ -n "${SEICHE_SHADER_DIR:-}" ]; then shaders=$SEICHE_SHADER_DIR; fi ;;
*) [ -d "$shaders" ] || die "--shaders: no directory '$shaders'"; shaders=$(cd "$shaders" && pwd) ;;
esac
mkdir -p "$out" || die "cannot create '$out'"
out=$(cd "$out" && pwd)
rm -rf "$out/scenes" "$out/bench" "$out/test-logs" "$out/suite.log" "$out/probe.log" "$out/report.md" "$out/report.json"
mkdir -p "$out/scenes" "$out/bench"

has_part() { case ",$parts," in *",$1,"*) return 0 ;; *) return 1 ;; esac; }

# Runs a command with a time limit (when coreutils' timeout is there); 124: timed out.
limited() {
    secs=$1
    shift
    if command -v timeout >/dev/null 2>&1; then timeout -k 10 "$secs" "$@"; else "$@"; fi
}

# A JSON string's contents: backslashes and quotes escaped, control characters dropped.
jstr() { printf '%s' "$1" | tr -d '\000-\037' | sed -e 's/\\/\\\\/g' -e 's/"/\\"/g'; }

now() { date +%s; }

# ---- the machine ----------------------------------------------------------------------

date_utc=$(date -u +%Y-%m-%dT%H:%M:%SZ)
host=$(uname -srm 2>/dev/null)
gpu_smi=""
if command -v nvidia-smi >/dev/null 2>&1; then
    gpu_smi=$(nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>/dev/null | head -n 1)
fi
commit=""
if command -v git >/dev/null 2>&1 && git -C "$root" rev-parse --git-dir >/dev/null 2>&1; then
    commit=$(git -C "$root" log -1 --format='%h %cd' --date=short 2>/dev/null)
    [ -z "$(git -C "$root" status --porcelain --untracked-files=no 2>/dev/null)" ] || commit="$commit (with local changes)"
fi

# The GL: seiche-bench prints "renderer: GL_RENDERER (GL_VERSION)" once it has a context;
# a one-step run at a thousand particles finds it (and whether GL 4.3 is there at all).
gl_full=""
probe_status="not run"
if [ -x "$bin/seiche-bench" ]; then
    # shellcheck disable=SC2086
    limited 120 "$bin/seiche-bench" --particles 1000 --steps 1 --warmup 0 ${shaders:+--shaders "$shaders"} \
        >"$out/probe.log" 2>&1
    rc=$?
    gl_full=$(sed -n 's/^renderer: //p' "$out/probe.log" | head -n 1)
    case $rc in
    0) probe_status="ok" ;;
    3) probe_status="no OpenGL 4.3 compute context (seiche-bench exit 3)" ;;
    *) probe_status="seiche-bench exit $rc: $(grep -v '^renderer:' "$out/probe.log" | head -n 1)" ;;
    esac
else
    probe_status="no $bin/seiche-bench"
fi

# "GL_RENDERER (GL_VERSION)": the version is the last parenthesised group (it may hold
# parentheses itself: "4.5 (Core Profile) Mesa 22.3.6").
split_gl() {
    printf '%s\n' "$gl_full" | awk -v want="$1" '{
        s = $0; n = length(s); r = s; v = ""
        if (substr(s, n, 1) == ")") {
            d = 0
            for (i = n; i > 0; i--) {
                c = substr(s, i, 1)
                if (c == ")") d++
                else if (c == "(" && --d == 0) break
            }
            if (i > 0) { r = substr(s, 1, i - 1); sub(/ +$/, "", r); v = substr(s, i + 1, n - i - 1) }
        }
        print (want == "renderer" ? r : v)
    }'
}
set_gl() {
    gl_renderer=$(split_gl renderer)
    gl_version=$(split_gl version)
}
set_gl

# ---- results so far (written into the report after each part) --------------------------

suite_status="not run"
suite_rc=""
suite_counts=""
suite_secs=""
failures=""           # space-separated: suite, scene:NAME, bench:N
scene_table="$out/scenes/table.tsv"   # one line per scene, tab-separated (run_scene)
bench_table="$out/bench/runs.txt"     # one line per size: seiche-bench's JSON object
: >"$scene_table"
: >"$bench_table"
bench_status="not run"
scenes_status="not run"

# ---- the report -----------------------------------------------------------------------

write_report() {
    overall="passed"
    [ -z "$failures" ] || overall="FAILED:$failures"
    md="$out/report.md"
    js="$out/report.json"
    {
        echo "# Seiche GPU check"
        echo
        echo "- date: $date_utc"
        echo "- GL renderer: \`${gl_renderer:-unknown}\`"
        echo "- driver (GL_VERSION): \`${gl_version:-unknown}\`"
        [ -z "$gpu_smi" ] || echo "- nvidia-smi: $gpu_smi"
        echo "- machine: $host"
        [ -z "$commit" ] || echo "- commit: $commit"
        if [ -n "$shaders" ]; then shaders_md="\`$shaders\`"; else shaders_md="the binaries' own default"; fi
        echo "- binaries: \`$bin\`; shaders: $shaders_md"
        echo "- GL probe: $probe_status"
        echo "- result: **$overall**"
        echo
        echo "## Test suite"
        echo
        case "$suite_status" in
        "not run"*) echo "$suite_status." | sed 's/^not run/Not run/' ;;
        *)
            echo "$suite_status: \`${suite_counts:-no summary line}\` (exit $suite_rc, ${suite_secs} s; log: suite.log, test-logs/)."
            if [ -s "$out/suite.skips" ]; then
                echo
                echo "Skipped:"
                echo
                sed 's/^/- /' "$out/suite.skips"
            fi
            if [ -s "$out/suite.failures" ]; then
                echo
                echo "Failed:"
                echo
                sed 's/^/- /' "$out/suite.failures"
            fi
            ;;
        esac
        echo
        echo "## Scenes ($frames frames each)"
        echo
        case "$scenes_status" in
        "not run"*) echo "$scenes_status." | sed 's/^not run/Not run/' ;;
        *)
            echo "ρ in kg/m³; overflow, NaN: the most particles in one step; GPU ms: mean over steps."
            [ -z "$reference" ] || echo "Reference for frame-0 ρ_max: \`$reference\` (tolerance $tolerance %)."
            echo
            if [ -n "$reference" ]; then
                echo "| scene | status | particles | ρ0 | frame-0 ρ_max | reference | max ρ_max | mean ρ_avg | overflow | NaN | outside | GPU ms/step | wall s |"
                echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
            else
                echo "| scene | status | particles | ρ0 | frame-0 ρ_max | max ρ_max | mean ρ_avg | overflow | NaN | outside | GPU ms/step | wall s |"
                echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
            fi
            awk -F'\t' -v ref="$reference" '{
                # name status rc rows particles rho0 r0 rmax ravg overflow nan outside ms secs refv note
                refcol = ref == "" ? "" : " " ($15 == "" ? "–" : $15) " |"
                printf "| %s | %s | %s | %s | %s |%s %s | %s | %s | %s | %s | %s | %s |\n",
                       $1, $2, $5, $6, $7, refcol, $8, $9, $10, $11, $12, $13, $14
            }' "$scene_table"
            if awk -F'\t' '$16 != "" { found = 1 } END { exit !found }' "$scene_table"; then
                echo
                awk -F'\t' '$16 != "" { print "- " $1 ": " $16 }' "$scene_table"
            fi
            echo
            echo "Per scene: scenes/NAME.csv (metrics), .png (last frame), .out and .err (the runner's output)."
            ;;
        esac
        echo
        echo "## Benchmark"
        echo
        case "$bench_status" in
        "not run"*) echo "$bench_status." | sed 's/^not run/Not run/' ;;
        *)
            echo "seiche-bench: dam break of a 1 m³ block, $bench_iterations iterations, 1 substep, dt 4 ms; median of $bench_steps steps after $bench_warmup warm-up. Times in ms per step (per stage: GPU, all iterations). Raw: bench/N.json."
            echo
            if [ -s "$bench_table" ]; then
                # Stage names from the first run's stage_ms object, in order.
                stages=$(head -n 1 "$bench_table" | sed 's/.*"stage_ms": {//; s/}.*//' | tr ',' '\n' | sed 's/^ *"\([^"]*\)".*/\1/' | tr '\n' ' ')
                printf '%s' '| particles | GPU ms/step | wall ms | CPU ms | max ρ/ρ0−1 % | mean compression % | NaN | overflow |'
                for s in $stages; do printf ' %s |' "$s"; done
                echo
                printf '|---:|---:|---:|---:|---:|---:|---:|---:|'
                for s in $stages; do printf '%s' '---:|'; done
                echo
                awk -v stages="$stages" '
                    function num(key,   m) {
                        if (match($0, "\"" key "\": -?[0-9.eE+-]+")) { m = substr($0, RSTART, RLENGTH); sub(/.*: /, "", m); return m }
                        return ""
                    }
                    {
                        printf "| %s | %.2f | %.2f | %.2f | %.2f | %.3f | %s | %s |", num("particles"), num("step_ms"),
                               num("wall_ms"), num("cpu_ms"), 100 * num("rho_err_max"), 100 * num("err_avg"), num("nan"), num("overflow")
                        n = split(stages, st, " ")
                        for (i = 1; i <= n; i++) printf " %.2f |", num(st[i])
                        printf "\n"
                    }' "$bench_table"
            fi
            if [ -s "$out/bench/failures.txt" ]; then
                echo
                sed 's/^/- failed: /' "$out/bench/failures.txt"
            fi
            ;;
        esac
    } >"$md"

    {
        echo "{"
        echo "  \"date\": \"$date_utc\","
        echo "  \"gl_renderer\": \"$(jstr "$gl_renderer")\","
        echo "  \"gl_version\": \"$(jstr "$gl_version")\","
        echo "  \"renderer\": \"$(jstr "$gl_full")\","
        echo "  \"nvidia_smi\": \"$(jstr "$gpu_smi")\","
        echo "  \"machine\": \"$(jstr "$host")\","
        echo "  \"commit\": \"$(jstr "$commit")\","
        echo "  \"binaries\": \"$(jstr "$bin")\","
        echo "  \"shaders\": \"$(jstr "$shaders")\","
        echo "  \"probe\": \"$(jstr "$probe_status")\","
        echo "  \"settings\": {\"frames\": $frames, \"size\": \"$(jstr "$size")\", \"bench_sizes\": [$bench_sizes], \"bench_steps\": $bench_steps, \"bench_warmup\": $bench_warmup, \"bench_iterations\": $bench_iterations, \"reference\": \"$(jstr "$reference")\", \"tolerance_percent\": $tolerance},"
        echo "  \"status\": \"$( [ -z "$failures" ] && echo passed || echo failed)\","
        printf '  "failures": ['
        sep=""
        for f in $failures; do printf '%s"%s"' "$sep" "$(jstr "$f")"; sep=", "; done
        echo "],"
        printf '  "suite": {"status": "%s"' "$(jstr "$suite_status")"
        if [ "$suite_status" != "not run" ]; then
            # shellcheck disable=SC2046 # three words, split on purpose
            set -- $(echo "$suite_counts" | sed -n 's/^\([0-9]*\) passed, \([0-9]*\) failed\(, \([0-9]*\) skipped\)\{0,1\}.*/\1 \2 \4/p')
            printf ', "exit": %s, "seconds": %s, "passed": %s, "failed": %s, "skipped": %s' "$suite_rc" "$suite_secs" \
                "${1:-null}" "${2:-null}" "${3:-0}"
            printf ', "skips": ['
            sep=""
            if [ -s "$out/suite.skips" ]; then
                while IFS= read -r line; do printf '%s"%s"' "$sep" "$(jstr "$line")"; sep=", "; done <"$out/suite.skips"
            fi
            printf '], "failures": ['
            sep=""
            if [ -s "$out/suite.failures" ]; then
                while IFS= read -r line; do printf '%s"%s"' "$sep" "$(jstr "$line")"; sep=", "; done <"$out/suite.failures"
            fi
            printf ']'
        fi
        echo "},"
        echo "  \"scenes_status\": \"$(jstr "$scenes_status")\","
        echo "  \"scenes\": ["
        awk -F'\t' '
            function n(v) { return (v == "" || v == "–") ? "null" : v }
            function s(v) { gsub(/\\/, "\\\\", v); gsub(/"/, "\\\"", v); return v }
            { rows[NR] = sprintf("    {\"scene\": \"%s\", \"status\": \"%s\", \"exit\": %s, \"frames\": %s, \"particles\": %s, \"rho0\": %s, " \
                  "\"rho_max_frame0\": %s, \"rho_max\": %s, \"rho_avg_mean\": %s, \"overflow_max\": %s, \"nan_max\": %s, " \
                  "\"outside_max\": %s, \"step_ms_mean\": %s, \"wall_s\": %s, \"reference_rho_max_frame0\": %s, \"note\": \"%s\"}",
                  s($1), s($2), n($3), n($4), n($5), n($6), n($7), n($8), n($9), n($10), n($11), n($12), n($13), n($14), n($15), s($16)) }
            END { for (i = 1; i <= NR; i++) print rows[i] (i < NR ? "," : "") }' "$scene_table"
        echo "  ],"
        echo "  \"bench_status\": \"$(jstr "$bench_status")\","
        echo "  \"bench\": ["
        awk '{ rows[NR] = "    " $0 } END { for (i = 1; i <= NR; i++) print rows[i] (i < NR ? "," : "") }' "$bench_table"
        echo "  ]"
        echo "}"
    } >"$js"
}

fail() { failures="$failures $1"; }

write_report

# ---- the suite ------------------------------------------------------------------------

if has_part suite; then
    if [ ! -x "$root/tests/run.sh" ]; then
        suite_status="not run: no tests/run.sh in $root"
        fail suite
    elif [ "$bin" != "$root/build/bin" ] && ! ls "$root"/build/bin/test_* >/dev/null 2>&1; then
        suite_status="not run: tests/run.sh uses $root/build/bin, which has no tests (--bin is $bin)"
        fail suite
    else
        echo "gpu_check: the test suite (log: $out/suite.log)"
        t0=$(now)
        limited $((limit * 4)) "$root/tests/run.sh" >"$out/suite.log" 2>&1
        suite_rc=$?
        suite_secs=$(($(now) - t0))
        suite_counts=$(grep -E '^[0-9]+ passed, [0-9]+ failed' "$out/suite.log" | tail -n 1)
        sed -n 's/^ *skipped //p' "$out/suite.log" >"$out/suite.skips"
        grep -E '^FAILED ' "$out/suite.log" | sed 's/^FAILED  *//; s/; stderr:$//' >"$out/suite.failures"
        [ -d "$root/build/test-logs" ] && cp -r "$root/build/test-logs" "$out/test-logs"
        if [ "$suite_rc" = 0 ]; then
            suite_status="passed"
        elif [ "$suite_rc" = 124 ] || [ "$suite_rc" = 137 ]; then
            suite_status="TIMED OUT after $((limit * 4)) s"
            fail suite
        else
            suite_status="FAILED"
            fail suite
        fi
        echo "gpu_check:   $suite_status: ${suite_counts:-no summary line} (${suite_secs} s)"
    fi
    write_report
fi

# ---- the scenes -----------------------------------------------------------------------

# The reference's frame-0 rho_max of a scene (empty when it has none).
reference_rho0() {
    [ -n "$reference" ] || return 0
    awk -v name="$1" 'index($0, "\"scene\": \"" name "\"") && match($0, /"rho_max_frame0": [0-9.eE+-]+/) {
        v = substr($0, RSTART, RLENGTH); sub(/.*: /, "", v); print v; exit }' "$reference"
}

run_scene() {
    script=$1
    name=$(basename "$script" .lua)
    base="$out/scenes/$name"
    echo "gpu_check: scene $name"
    t0=$(now)
    # shellcheck disable=SC2086
    limited "$limit" "$bin/seiche" --headless --frames "$frames" ${size:+--size "$size"} ${shaders:+--shaders "$shaders"} \
        --metrics "$base.csv" --screenshot "$base.png" "$script" >"$base.out" 2>"$base.err"
    rc=$?
    secs=$(($(now) - t0))
    [ -n "$gl_full" ] || { gl_full=$(sed -n 's/.* ms GPU per step, //p' "$base.out" | head -n 1); set_gl; }
    # The metrics, by column name: frame-0 and max rho_max, mean rho_avg, the most
    # overflowing / NaN / outside particles in one step, mean step_ms.
    stats=$(awk -F, '
        NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; nf = NF; next }
        NF != nf { next } # a row cut short (a run stopped while writing it)
        {
            rows++
            if ($col["frame"] == 0) r0 = $col["rho_max"]
            if (rows == 1 || $col["rho_max"] > rmax) rmax = $col["rho_max"]
            ravg += $col["rho_avg"]; ms += $col["step_ms"]
            if ($col["overflow"] > ov) ov = $col["overflow"]
            if ($col["nan"] > nan) nan = $col["nan"]
            if ($col["outside"] > outside) outside = $col["outside"]
            particles = $col["particles"]; rho0 = $col["rho0"]
        }
        END {
            if (rows == 0) { print "0"; exit }
            printf "%d\t%d\t%.0f\t%s\t%.2f\t%.2f\t%d\t%d\t%d\t%.3f\n", rows, particles, rho0, r0 == "" ? "–" : sprintf("%.2f", r0),
                   rmax, ravg / rows, ov, nan, outside, ms / rows
        }' "$base.csv" 2>/dev/null)
    [ -n "$stats" ] || stats=0
    rows=${stats%%	*}
    status="ok"
    note=""
    if [ "$rc" = 124 ] || [ "$rc" = 137 ]; then
        status="TIMED OUT"
        note="stopped after $limit s"
    elif [ "$rc" != 0 ]; then
        status="FAILED (exit $rc)"
        note=$(grep -v '^ *$' "$base.err" | head -n 1)
    fi
    if [ "$rows" = 0 ]; then
        [ "$status" != ok ] || status="FAILED (no metrics)"
        stats=$(printf '0\t–\t–\t–\t–\t–\t–\t–\t–\t–')
    else
        nan=$(printf '%s\n' "$stats" | cut -f8)
        [ "$nan" = 0 ] || { [ "$status" != ok ] || status="FAILED (NaN)"; }
        [ "$rows" -ge "$frames" ] || note="${note:+$note; }$rows of $frames frames in the metrics"
        ov=$(printf '%s\n' "$stats" | cut -f7)
        [ "$ov" = 0 ] || note="${note:+$note; }neighbour lists overflowed (up to $ov particles in a step)"
    fi
    refv=$(reference_rho0 "$name")
    if [ -n "$reference" ]; then
        r0=$(printf '%s\n' "$stats" | cut -f4)
        if [ -z "$refv" ]; then
            note="${note:+$note; }not in the reference"
        elif [ "$r0" != "–" ]; then
            verdict=$(awk -v a="$r0" -v b="$refv" -v tol="$tolerance" 'BEGIN {
                d = b != 0 ? 100 * (a - b) / b : 0; printf "%s %+.2f", (d > tol || d < -tol) ? "out" : "in", d }')
            note="${note:+$note; }frame-0 rho_max ${verdict#* } % against the reference"
            case "$verdict" in out*) [ "$status" != ok ] || status="FAILED (frame 0 differs)" ;; esac
        fi
    fi
    [ "$status" = ok ] || fail "scene:$name"
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$status" "$rc" "$stats" "$secs" "$refv" "$(printf '%s' "$note" | tr '\t' ' ')" \
        >>"$scene_table"
    echo "gpu_check:   $status ($secs s)"
}

if has_part scenes; then
    scenes_status="ran"
    if [ ! -x "$bin/seiche" ]; then
        scenes_status="not run: no $bin/seiche"
        fail scenes
    else
        found=0
        for script in "$scenes_dir"/*.lua; do
            [ -f "$script" ] || continue
            found=1
            run_scene "$script"
            write_report
        done
        [ "$found" = 1 ] || { scenes_status="not run: no scenes in $scenes_dir"; fail scenes; }
    fi
    write_report
fi

# ---- the benchmark --------------------------------------------------------------------

if has_part bench; then
    bench_status="ran"
    if [ ! -x "$bin/seiche-bench" ]; then
        bench_status="not run: no $bin/seiche-bench"
        fail bench
    else
        : >"$out/bench/failures.txt"
        for n in $(echo "$bench_sizes" | tr ',' ' '); do
            echo "gpu_check: benchmark at $n particles"
            # shellcheck disable=SC2086
            limited "$limit" "$bin/seiche-bench" --particles "$n" --iterations "$bench_iterations" --steps "$bench_steps" \
                --warmup "$bench_warmup" --json "$out/bench/$n.json" ${shaders:+--shaders "$shaders"} \
                >"$out/bench/$n.out" 2>"$out/bench/$n.err"
            rc=$?
            if [ "$rc" = 0 ] && grep -q '"particles"' "$out/bench/$n.json" 2>/dev/null; then
                grep '"particles"' "$out/bench/$n.json" | sed 's/^ *//; s/,$//' >>"$bench_table"
                echo "gpu_check:   ok"
            else
                why=$(grep -v '^ *$' "$out/bench/$n.err" 2>/dev/null | head -n 1)
                [ "$rc" != 124 ] && [ "$rc" != 137 ] || why="timed out after $limit s"
                echo "$n particles: exit $rc${why:+: $why}" >>"$out/bench/failures.txt"
                fail "bench:$n"
                echo "gpu_check:   FAILED (exit $rc)"
            fi
            write_report
        done
    fi
    write_report
fi

write_report
echo "gpu_check: report: $out/report.md, $out/report.json"
if [ -n "$failures" ]; then
    echo "gpu_check: FAILED:$failures"
    exit 1
fi
echo "gpu_check: passed"
exit 0
