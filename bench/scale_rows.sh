#!/bin/sh
# Issue 28, the scale rows of bench/README.md: `vdbmesh mesh` end to end on the bunny CT tiled
# k x k x k (bench/make_tiled_scan.py writes it; the bench never ships data), with the time and
# peak resident memory of each run (/usr/bin/time -f "%e %M", children included), its
# triangles, and whether its file is byte-identical to the unbounded run's.
# Usage: bench/scale_rows.sh VDBMESH FOLDER K [MEMORY] [RANKS...]
#   FOLDER holds (or gets) bunny_kK.raw and bunny_kK.vdb; MEMORY (default 1G) is the --memory
#   limit; each RANKS runs the .vdb under mpirun -np RANKS, one thread a rank, against -np 1.
#   K = 6 (41 GB raw) runs only from the raw scan with MEMORY: nothing else fits in memory.
set -eu
vdbmesh=$1 folder=$2 k=$3 memory=${4:-1G}
shift $(($# < 4 ? $# : 4))
here=$(dirname "$0")
raw=$folder/bunny_k$k.raw vdb=$folder/bunny_k$k.vdb
dims="$((512 * k)),$((512 * k)),$((361 * k))"
scan="--raw-dims $dims --raw-type i16 --raw-endian big --iso 1200.5"
[ -e "$raw" ] || python3 "$here/make_tiled_scan.py" --k "$k" -o "$raw" --quiet
work=$(mktemp -d "$folder/scale.XXXXXX")
trap 'rm -rf "$work"' EXIT
row() {  # label, reference label ("" for none), then the command after `vdbmesh`
    label=$1 reference=$2
    shift 2
    /usr/bin/time -f "%e %M" -o "$work/time" "$@" -q --json -o "$work/$label.ply" >"$work/$label.json"
    read -r seconds kb <"$work/time"
    triangles=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['triangles'])" "$work/$label.json" 2>/dev/null || echo "-")
    same="-"
    [ -n "$reference" ] && same=$(cmp -s "$work/$label.ply" "$work/$reference.ply" && echo yes || echo no)
    printf '| %s | %s | %s s | %s MB | %s | %s |\n' "$k" "$label" "$seconds" "$((kb / 1024))" "$triangles" "$same"
}
echo "| k | run | time | peak | triangles | same bytes |"
echo "|---|---|---|---|---|---|"
if [ "$k" -lt 6 ]; then
    [ -e "$vdb" ] || "$vdbmesh" convert "$raw" $scan -q -o "$vdb"
    row "dc-vdb" "" "$vdbmesh" mesh "$vdb" --error 0.25
    row "dc-vdb-memory-$memory" dc-vdb "$vdbmesh" mesh "$vdb" --error 0.25 --memory "$memory"
    row "dc-raw-memory-$memory" dc-vdb "$vdbmesh" mesh "$raw" $scan --error 0.25 --memory "$memory"
    row "openvdb-vdb-a0.25" "" "$vdbmesh" mesh "$vdb" --method openvdb --adaptivity 0.25
    for ranks in "$@"; do
        [ -e "$work/np1.ply" ] || row np1 dc-vdb mpirun --allow-run-as-root --oversubscribe -np 1 "$vdbmesh" mesh "$vdb" --error 0.25 --threads 1
        row "np$ranks" dc-vdb mpirun --allow-run-as-root --oversubscribe -np "$ranks" "$vdbmesh" mesh "$vdb" --error 0.25 --threads 1
    done
else
    row "dc-raw-memory-$memory" "" "$vdbmesh" mesh "$raw" $scan --error 0.25 --memory "$memory"
    /usr/bin/time -f "%e %M" -o "$work/time" "$vdbmesh" check "$work/dc-raw-memory-$memory.ply" --memory "$memory" --json >"$work/check.json" || true
    read -r seconds kb <"$work/time"
    echo "check --memory $memory: $seconds s, $((kb / 1024)) MB: $(python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print({k: d.get(k) for k in ('closed', 'boundary_edges', 'nonmanifold_edges', 'nonmanifold_vertices', 'misoriented_edges', 'outward', 'components', 'triangles')})" "$work/check.json")"
fi
