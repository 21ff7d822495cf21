#!/bin/sh
# Side-by-side timing of shader variants on one machine (docs/performance.md, "Kernel
# changes"): seiche-bench runs each variant's shader tree in turn at each size, ROUNDS
# times, interleaved (A B C A B C ...), so that the machine's drift lands on all of them;
# one table of every run's line. A variant is NAME=DIR, DIR a copy of shaders/ (the
# binaries are the same for all: only what the shaders do may differ).
#   tools/gpu_ab.sh [--sizes N,N] [--iterations K] [--substeps S] [--steps M] [--warmup W]
#                   [--rounds R] [--timeout SECONDS] [--bin DIR] [--out DIR] NAME=DIR...
# Writes OUT/NAME-N-R.txt (seiche-bench's output) and OUT/table.txt; exit 1 when a run failed.
usage() { sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'; }
here=$(cd "$(dirname "$0")" && pwd) || exit 2
bin="$here/../build/bin" out=build/gpu-ab sizes=262144,1048576 iterations=4 substeps=1 steps=60 warmup=10 rounds=1
limit=60
while [ $# -gt 0 ]; do
    case $1 in
    --sizes) sizes=$2; shift 2 ;;
    --iterations) iterations=$2; shift 2 ;;
    --substeps) substeps=$2; shift 2 ;;
    --steps) steps=$2; shift 2 ;;
    --warmup) warmup=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    --timeout) limit=$2; shift 2 ;;
    --bin) bin=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --help) usage; exit 0 ;;
    -*) echo "gpu_ab: unknown option $1" >&2; usage >&2; exit 2 ;;
    *=*) break ;;
    *) echo "gpu_ab: a variant is NAME=DIR (got '$1')" >&2; exit 2 ;;
    esac
done
[ $# -gt 0 ] || { echo "gpu_ab: no variants (NAME=DIR ...)" >&2; exit 2; }
for v in "$@"; do
    [ -f "${v#*=}/fluid/common.glsl" ] || { echo "gpu_ab: ${v#*=} is not a shader tree (no fluid/common.glsl)" >&2; exit 2; }
done
mkdir -p "$out"
table="$out/table.txt"
failed=0
: >"$table"
for n in $(echo "$sizes" | tr ',' ' '); do
    r=1
    while [ "$r" -le "$rounds" ]; do
        for v in "$@"; do
            name=${v%%=*} dir=${v#*=}
            f="$out/$name-$n-$r.txt"
            timeout -k 5 "$limit" "$bin/seiche-bench" --particles "$n" --iterations "$iterations" --substeps "$substeps" \
                --steps "$steps" --warmup "$warmup" --shaders "$dir" >"$f" 2>&1
            rc=$?
            [ -s "$table" ] || grep -m1 '^particles' "$f" | sed 's/^/variant  /' >>"$table"
            line=$(grep -E '^ *[0-9]' "$f" | tail -n 1)
            if [ "$rc" = 0 ] && [ -n "$line" ]; then
                echo "$name  $line" >>"$table"
            else
                echo "$name  $n particles: exit $rc" >>"$table"
                failed=1
            fi
        done
        r=$((r + 1))
    done
done
cat "$table"
exit $failed
