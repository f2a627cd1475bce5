#!/bin/sh
# Issue 28, the scale model simulated (docs/scale.md, "64 ranks simulated"): `vdbmesh mesh` as
# RANKS ranks, one plain process per rank in turn on this machine (VDBMESH_SIMULATE_RANKS, see
# src/ranks/simulated_ranks.h), the last rank first; rank 0 gathers the others' parts from files
# and writes the mesh. Prints each rank's time, peak resident memory (/usr/bin/time) and the
# bytes it would send, a summary, and whether rank 0's file is byte-identical to a plain run's.
# Usage: bench/simulate_ranks.sh VDBMESH GRID.vdb RANKS [MESH OPTIONS...]
#   e.g. bench/simulate_ranks.sh build/vdbmesh bunny_k3.vdb 64 --error 0.25 --memory 200M
set -eu
vdbmesh=$1 grid=$2 ranks=$3
shift 3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir "$work/parts"
echo "| rank | time | peak | bytes sent |"
echo "|---|---|---|---|"
rank=$((ranks - 1))
while [ "$rank" -ge 0 ]; do
    VDBMESH_SIMULATE_RANKS="$rank/$ranks:$work/parts" /usr/bin/time -f "%e %M" -o "$work/time" \
        "$vdbmesh" mesh "$grid" "$@" --threads 1 -q -o "$work/ranks.ply"
    read -r seconds kb <"$work/time"
    sent=0
    [ "$rank" -gt 0 ] && sent=$(wc -c <"$work/parts/part-$rank")
    echo "| $rank | $seconds s | $((kb / 1024)) MB | $sent |" | tee -a "$work/rows"
    rank=$((rank - 1))
done
awk -F'|' '{ t = $3 + 0; m = $4 + 0; b = $5 + 0; n++; st += t; sb += b
             if (n == 1 || t > tt) tt = t; if (n == 1 || t < lt) lt = t
             if (n == 1 || m > tm) tm = m; if (n == 1 || m < lm) lm = m; if (b > tb) tb = b }
           END { printf "time per rank %.1f .. %.1f s (sum %.0f s); peak %d .. %d MB; sent at most %d bytes, %d in all\n", lt, tt, st, lm, tm, tb, sb }' "$work/rows"
"$vdbmesh" mesh "$grid" "$@" -q -o "$work/plain.ply"
cmp -s "$work/ranks.ply" "$work/plain.ply" && echo "rank 0's file: the same bytes as the plain run" || echo "rank 0's file DIFFERS from the plain run"
