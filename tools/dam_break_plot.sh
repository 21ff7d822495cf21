#!/bin/sh
# The dam-break front against Martin & Moyce (1952) at three particle sizes, and the same
# without wall friction: runs tools/dam_break_front.lua headless (a few minutes: the 2.5 mm
# run has 38 400 particles), keeps the T Z columns in OUT_DIR/dam_break_front_*.dat and
# plots them with the experiment's Table 2 (docs/data/martin_moyce_1952.txt, first block)
# into OUT_DIR/dam_break_front.png. docs/validation.md, "Dam-break front".
#   tools/dam_break_plot.sh [OUT_DIR]
set -eu
cd "$(dirname "$0")/.."
out=${1:-docs/plots}
mkdir -p "$out"
command -v gnuplot >/dev/null || { echo "dam_break_plot: gnuplot is missing (apt-get install gnuplot-nox)"; exit 2; }

run() { # file radius [more runner options]
    file=$1 r=$2
    shift 2
    build/bin/seiche --headless --quiet --frames 21 --set fluid.particle_radius="$r" "$@" \
        tools/dam_break_front.lua | awk '$1 == "T" { print $2, $4 }' > "$file"
}
for r in 0.01 0.005 0.0025; do
    run "$out/dam_break_front_$r.dat" "$r" # the library's wall friction
done
run "$out/dam_break_front_0.0025_frictionless.dat" 0.0025 --set fluid.wall_friction=0
# The experiment: the first data block of the file (its Table 2).
awk '/^# block:/ { b++ } b == 1 && $0 !~ /^#/ && NF == 2' docs/data/martin_moyce_1952.txt > "$out/martin_moyce_table2.dat"

gnuplot <<GP
set terminal pngcairo size 900,560 font "sans,11" noenhanced
set output "$out/dam_break_front.png"
set title "Dam-break surge front: Z = front / a against T = t sqrt(2g/a)"
set xlabel "T"
set ylabel "Z"
set key top left
set grid
set xrange [0:3.5]
plot "$out/martin_moyce_table2.dat" using 1:2 with points pt 7 ps 1.3 lc rgb "black" title "Martin & Moyce 1952, Table 2", \
     "$out/dam_break_front_0.01.dat" using 1:2 with lines lw 2 title "r 10 mm", \
     "$out/dam_break_front_0.005.dat" using 1:2 with lines lw 2 title "r 5 mm", \
     "$out/dam_break_front_0.0025.dat" using 1:2 with lines lw 2 title "r 2.5 mm", \
     "$out/dam_break_front_0.0025_frictionless.dat" using 1:2 with lines lw 1 dt 2 title "r 2.5 mm, frictionless walls"
GP
echo "dam_break_plot: $out/dam_break_front.png"
