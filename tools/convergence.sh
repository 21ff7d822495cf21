#!/bin/sh
# The convergence study of docs/performance.md: mean compression error and maximum density
# error of the reference dam break against iterations, for 1, 2 and 4 substeps, and
# against GPU time per step. Writes OUT_DIR/convergence.json, .dat and .png.
#   tools/convergence.sh [OUT_DIR] [PARTICLES]
set -eu
cd "$(dirname "$0")/.."
out=${1:-docs/plots}
n=${2:-16000}
mkdir -p "$out"
build/bin/seiche-bench --particles "$n" --iterations 1,2,3,4,6,8 --substeps 1,2,4 --steps 30 --warmup 20 \
    --json "$out/convergence.json" | tee "$out/convergence.txt"
# particles iter sub step_ms wall_ms cpu_ms rho_avg% err_avg% rho_max% ...
awk 'NR > 3 && $1 ~ /^[0-9]+$/ { print $3, $2, $4, $8, $9 }' "$out/convergence.txt" > "$out/convergence.dat"
gnuplot <<GP
set terminal pngcairo size 1100,450 font "sans,11" noenhanced
set output "$out/convergence.png"
set multiplot layout 1,2 title "Reference dam break ($n particles, dt 4 ms): density error after 0.08 s"
set logscale y
set grid
set xlabel "iterations per substep"
set ylabel "error (%)"
set key top right
plot for [s in "1 2 4"] "$out/convergence.dat" using (\$1 == s ? \$2 : 1/0):4 with linespoints lw 2 title "mean compression, ".s." substeps", \
     for [s in "1 2 4"] "$out/convergence.dat" using (\$1 == s ? \$2 : 1/0):5 with linespoints dt 2 lw 2 title "max, ".s." substeps"
set xlabel "GPU time per step (ms, llvmpipe)"
unset logscale x
plot for [s in "1 2 4"] "$out/convergence.dat" using (\$1 == s ? \$3 : 1/0):4 with linespoints lw 2 title "mean compression, ".s." substeps"
unset multiplot
GP
echo "convergence: $out/convergence.png"
