#!/bin/sh
# A side-by-side run against a peer solver (docs/performance.md, "Against SPlisHSPlasH"):
# the reference dam break at each size, Seiche's seiche-bench and the peer alternating
# ROUNDS times, so both see the same machine in the same minutes.
#   PEER_RUN=/path/to/run_peer.sh tools/peer_pair.sh [SIZES] [ROUNDS] [OUT]
# PEER_RUN N must run the peer on the same scene (a 1 m cube of water in a 4 x 3 x 1.5 m
# tank, N particles, ITERATIONS iterations (default 3; exported to the peer's script as
# PEER_ITERATIONS), 1 substep, dt 4 ms, steps 11-300) and print, last, a line
# "peer N=... median_ms=... mean_ms=... mean_compression=...% max=...%". Seiche runs the same
# window: 290 steps after 10 warm-up. SIZES default 15625,64000 (a cube number each, so
# both place the same lattice); ROUNDS default 3. Writes OUT (default
# docs/bench/peer_pair.txt): every run's summary line, then the medians per size.
set -eu
cd "$(dirname "$0")/.."
: "${PEER_RUN:?set PEER_RUN to the peer's run script (docs/performance.md)}"
sizes=${1:-15625,64000}
rounds=${2:-3}
out=${3:-docs/bench/peer_pair.txt}
bin=${SEICHE_BIN:-build/bin}
iterations=${ITERATIONS:-3}
export PEER_ITERATIONS=$iterations
mkdir -p "$(dirname "$out")"
{
    echo "# tools/peer_pair.sh $sizes $rounds, $iterations iterations, $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores"
    echo "# $($bin/seiche-bench --particles 1000 --steps 1 --warmup 0 | sed -n 's/^renderer: //p')"
    echo "# PEER_RUN=$PEER_RUN OMP_NUM_THREADS=${OMP_NUM_THREADS:-2} OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}"
} > "$out"
for n in $(echo "$sizes" | tr ',' ' '); do
    r=1
    while [ "$r" -le "$rounds" ]; do
        # particles iter sub tank mem_MiB step_ms wall_ms cpu_ms rho_avg% err_avg% rho_max% ... metrics
        "$bin/seiche-bench" --particles "$n" --iterations "$iterations" --substeps 1 --steps 290 --warmup 10 |
            awk -v r="$r" '$1 ~ /^[0-9]+$/ { printf "seiche N=%d round=%d gpu_ms=%.2f wall_ms=%.2f metrics_ms=%.2f mean_compression=%.3f%% max=%.2f%%\n",
                                            $1, r, $6, $7, $NF, $10, $11 }' | tee -a "$out"
        "$PEER_RUN" "$n" 2>&1 | grep '^peer N=' | tail -n 1 | sed "s/^peer N=$n /peer N=$n round=$r /" | tee -a "$out"
        r=$((r + 1))
    done
done
# Medians per size and solver (of the per-run medians over steps).
awk '/^(seiche|peer) / {
        split($2, a, "="); key = $1 " " a[2]
        for (i = 3; i <= NF; i++) { split($i, kv, "="); v = kv[2]; sub(/%$/, "", v); vals[key, kv[1]] = vals[key, kv[1]] " " v }
        keys[key] = 1
     }
     function median(s,   n, x, i, j, t) {
        n = split(s, x, " ")
        for (i = 1; i <= n; i++) for (j = i + 1; j <= n; j++) if (x[j] + 0 < x[i] + 0) { t = x[i]; x[i] = x[j]; x[j] = t }
        return n % 2 ? x[(n + 1) / 2] : (x[n / 2] + x[n / 2 + 1]) / 2
     }
     END {
        for (k in keys) {
            split(k, p, " ")
            if (p[1] == "seiche")
                printf "median %s N=%s gpu_ms=%s wall_ms=%s wall_without_metrics_ms=%.2f mean_compression=%s%% max=%s%%\n", p[1], p[2],
                       median(vals[k, "gpu_ms"]), median(vals[k, "wall_ms"]), median(vals[k, "wall_ms"]) - median(vals[k, "metrics_ms"]),
                       median(vals[k, "mean_compression"]), median(vals[k, "max"])
            else
                printf "median %s N=%s median_ms=%s mean_compression=%s%% max=%s%%\n", p[1], p[2],
                       median(vals[k, "median_ms"]), median(vals[k, "mean_compression"]), median(vals[k, "max"])
        }
     }' "$out" | sort | tee -a "$out"
# Error against time, both solvers, from this run's medians: OUT's name with .png.
if command -v gnuplot > /dev/null; then
    png=${out%.txt}.png
    awk '/^median seiche/ { for (i = 3; i <= NF; i++) { split($i, kv, "="); v[kv[1]] = kv[2] } sub(/%/, "", v["mean_compression"]); sub(/%/, "", v["max"])
                            print "seiche", substr($3, 3), v["wall_ms"], v["mean_compression"], v["max"] }
         /^median peer/ { for (i = 3; i <= NF; i++) { split($i, kv, "="); v[kv[1]] = kv[2] } sub(/%/, "", v["mean_compression"]); sub(/%/, "", v["max"])
                          print "peer", substr($3, 3), v["median_ms"], v["mean_compression"], v["max"] }' "$out" > "$out.dat"
    gnuplot <<GP
set terminal pngcairo size 1100,450 font "sans,11" noenhanced
set output "$png"
set multiplot layout 1,2 title "Reference dam break, $iterations iterations x 1 substep, dt 4 ms, steps 11-300: paired run ($(sed -n '1s/^# //p' "$out"))"
set logscale xy
set grid
set key top left
set xlabel "wall ms per step (median)"
set ylabel "mean compression error (%)"
plot "$out.dat" using (strcol(1) eq "seiche" ? \$3 : 1/0):4:(sprintf("%d", \$2)) with labels point pt 7 ps 1.5 lc rgb "#1f77b4" offset char 0,1 title "Seiche (llvmpipe)", \
     "$out.dat" using (strcol(1) eq "peer" ? \$3 : 1/0):4:(sprintf("%d", \$2)) with labels point pt 5 ps 1.5 lc rgb "#d62728" offset char 0,1 title "SPlisHSPlasH PBF (CPU, 2 threads)"
set ylabel "worst density over rho0 (%)"
plot "$out.dat" using (strcol(1) eq "seiche" ? \$3 : 1/0):5:(sprintf("%d", \$2)) with labels point pt 7 ps 1.5 lc rgb "#1f77b4" offset char 0,1 title "Seiche (llvmpipe)", \
     "$out.dat" using (strcol(1) eq "peer" ? \$3 : 1/0):5:(sprintf("%d", \$2)) with labels point pt 5 ps 1.5 lc rgb "#d62728" offset char 0,1 title "SPlisHSPlasH PBF (CPU, 2 threads)"
unset multiplot
GP
    echo "plot: $png"
fi
