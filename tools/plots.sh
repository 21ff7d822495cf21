#!/bin/sh
# The report's plots, for both paper scenes: maximum and mean density against rho0 over
# time, and the mean GPU time per solver stage. Runs each scene headless with --metrics,
# then gnuplot writes PNGs into docs/plots/ (or the directory given).
#   tools/plots.sh [OUT_DIR] [FRAMES]        (make plots)
set -eu
cd "$(dirname "$0")/.."
out=${1:-docs/plots}
frames=${2:-300}
mkdir -p "$out"
command -v gnuplot >/dev/null || { echo "plots: gnuplot is missing (apt-get install gnuplot-nox)"; exit 2; }

for scene in dam_break prefilled_drop; do
    csv="$out/$scene.csv"
    build/bin/seiche --headless --frames "$frames" --metrics "$csv" "scripts/scenes/$scene.lua"

    gnuplot <<GP
set datafile separator ","
set terminal pngcairo size 900,500 font "sans,11" noenhanced
set output "$out/${scene}_density.png"
set title "$scene: density against rest density (GPU reduction, every frame)"
set xlabel "time (s)"
set ylabel "density (kg/m^3)"
set key bottom right
set grid
plot "$csv" using 2:5 with lines lw 2 title "max", \
     "$csv" using 2:6 with lines lw 2 title "mean", \
     "$csv" using 2:4 with lines lw 1 dt 2 lc rgb "black" title "rest density"
GP

    # Mean per stage (columns 8.. are <stage>_ms, up to the nan column).
    awk -F, 'NR == 1 { for (i = 8; i <= NF; i++) if ($i ~ /_ms$/) { name[i] = $i; last = i }; next }
             NR > 2 { n++; for (i = 8; i <= last; i++) sum[i] += $i }
             END { for (i = 8; i <= last; i++) { s = name[i]; sub(/_ms$/, "", s); printf "%s %.4f\n", s, sum[i] / n } }' \
        "$csv" > "$out/${scene}_stages.dat"
    gnuplot <<GP
set terminal pngcairo size 900,500 font "sans,11" noenhanced
set output "$out/${scene}_stages.png"
set title "$scene: mean GPU time per stage and step (all substeps and iterations)"
set ylabel "ms"
set style fill solid 0.8
set boxwidth 0.7
set xtics rotate by -35
set grid ytics
unset key
plot "$out/${scene}_stages.dat" using 0:2:xtic(1) with boxes lc rgb "#3070b0"
GP
    echo "plots: $out/${scene}_density.png $out/${scene}_stages.png"
done
