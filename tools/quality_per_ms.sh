#!/bin/sh
# Quality per millisecond (docs/performance.md): the reference dam break at several particle
# counts, each with several iterations x substeps choices, one seiche-bench run per count;
# prints the time per step and the density error over the same window (mean compression,
# worst density) of every case, and plots error against GPU time per step.
#   tools/quality_per_ms.sh [OUT_DIR [SPEC...]]
# SPEC: a particle count N, for the cases 1x1 2x1 3x1 4x1 2x2 3x2 2x4 (iterations x
# substeps), or N:ITxSUB,ITxSUB,... for those cases only (default specs: 16000 64000).
# SPEC "plot" alone runs nothing: the table and the plot again from OUT_DIR's .dat and .txt
# (after appending the lines of another run to them, say).
# The window is seiche-bench's default, steps 11-70 of 4 ms (0.04-0.28 s into the collapse)
# whatever the case (STEPS, WARMUP in the environment change it).
# Writes OUT_DIR/quality_per_ms.txt (the benchmark's tables), .dat (one line per case:
# particles iterations substeps step_ms err_avg% rho_max%), .md (the table) and .png.
set -eu
cd "$(dirname "$0")/.."
out=${1:-docs/plots}
[ $# -gt 0 ] && shift
[ $# -gt 0 ] || set -- 16000 64000
steps=${STEPS:-60}
warmup=${WARMUP:-10}
sizes=""
bin=${SEICHE_BIN:-build/bin}
mkdir -p "$out"
plot_only=0
[ "$*" = plot ] && plot_only=1 && set --
[ "$plot_only" = 1 ] || { : > "$out/quality_per_ms.txt"; : > "$out/quality_per_ms.dat"; }
for spec in "$@"; do
    n=${spec%%:*}
    cases="1x1 2x1 3x1 4x1 2x2 3x2 2x4"
    [ "$n" = "$spec" ] || cases=$(echo "${spec#*:}" | tr ',' ' ')
    sizes="$sizes${sizes:+,}$n"
    for c in $cases; do
        it=${c%x*}
        sub=${c#*x}
        "$bin/seiche-bench" --particles "$n" --iterations "$it" --substeps "$sub" --steps "$steps" \
            --warmup "$warmup" > "$out/.qpm_run.txt"
        cat "$out/.qpm_run.txt" >> "$out/quality_per_ms.txt"
        # particles iter sub tank mem_MiB step_ms wall_ms cpu_ms rho_avg% err_avg% rho_max% ...
        awk '$1 ~ /^[0-9]+$/ { print $1, $2, $3, $6, $10, $11 }' "$out/.qpm_run.txt" | tee -a "$out/quality_per_ms.dat"
    done
done
rm -f "$out/.qpm_run.txt"
[ "$plot_only" = 0 ] || sizes=$(awk '{ print $1 }' "$out/quality_per_ms.dat" | sort -n | uniq | paste -sd, -)
renderer=$(sed -n 's/^renderer: //p' "$out/quality_per_ms.txt" | head -n 1)
{
    echo "Reference dam break, dt 4 ms, steps $((warmup + 1))-$((warmup + steps)); $renderer; $(date -u +%Y-%m-%d)"
    echo
    echo "| particles | iterations x substeps | GPU ms per step | mean compression | worst density | within +10 % and 1 % |"
    echo "|---:|---|---:|---:|---:|---|"
    awk '{ ok = ($6 <= 10 && $5 <= 1) ? "yes" : "no"
           printf "| %d | %d x %d | %.1f | %.3f %% | %+.1f %% | %s |\n", $1, $2, $3, $4, $5, $6, ok }' "$out/quality_per_ms.dat"
} > "$out/quality_per_ms.md"
cat "$out/quality_per_ms.md"
if command -v gnuplot > /dev/null; then
    gnuplot <<GP
set terminal pngcairo size 1100,450 font "sans,11" noenhanced
set output "$out/quality_per_ms.png"
set multiplot layout 1,2 title "Reference dam break, dt 4 ms: density error against GPU time per step ($renderer)"
set logscale xy
set grid
set xlabel "GPU time per step (ms)"
set key outside bottom center horizontal
set ylabel "mean compression error (%)"
plot for [n in "$(echo "$sizes" | tr ',' ' ')"] "$out/quality_per_ms.dat" using (\$1 >= n*0.97 && \$1 <= n*1.03 ? \$4 : 1/0):5:(sprintf("%dx%d", \$2, \$3)) \
     with labels point pt 7 offset char 0,0.8 notitle, \
     for [n in "$(echo "$sizes" | tr ',' ' ')"] "$out/quality_per_ms.dat" using (\$1 >= n*0.97 && \$1 <= n*1.03 ? \$4 : 1/0):5 with points pt 7 ps 1.2 title n." particles"
set ylabel "worst density over rho0 (%)"
plot for [n in "$(echo "$sizes" | tr ',' ' ')"] "$out/quality_per_ms.dat" using (\$1 >= n*0.97 && \$1 <= n*1.03 ? \$4 : 1/0):6:(sprintf("%dx%d", \$2, \$3)) \
     with labels point pt 7 offset char 0,0.8 notitle, \
     for [n in "$(echo "$sizes" | tr ',' ' ')"] "$out/quality_per_ms.dat" using (\$1 >= n*0.97 && \$1 <= n*1.03 ? \$4 : 1/0):6 with points pt 7 ps 1.2 title n." particles", \
     10 with lines dt 2 lc "black" title "+10 %"
unset multiplot
GP
    echo "quality per ms: $out/quality_per_ms.png"
fi
