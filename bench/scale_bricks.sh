#!/bin/sh
# Issue 28, bricks: `vdbmesh mesh` of one .vdb whole and with --memory limits (bricks, spill,
# streamed file), end-to-end seconds and peak resident memory (/usr/bin/time -f %M), and
# whether the file is byte-identical to the whole-grid run's.
# Usage: bench/scale_bricks.sh VDBMESH GRID.vdb ERROR MEMORY... (e.g. build/vdbmesh bunny.vdb 0.25 400M 250M)
set -eu
vdbmesh=$1 grid=$2 error=$3
shift 3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
run() {  # label, then the extra options
    label=$1
    shift
    /usr/bin/time -f "%e %M" -o "$work/time" "$vdbmesh" mesh "$grid" --error "$error" -o "$work/$label.ply" -q "$@"
    read -r seconds kb <"$work/time"
    same=$(cmp -s "$work/$label.ply" "$work/whole.ply" && echo yes || echo no)
    printf '| %s | %s s | %s MB | %s |\n' "$label" "$seconds" "$((kb / 1024))" "$same"
}
echo "| run | time | peak | same bytes as whole |"
echo "|---|---|---|---|"
run whole
for memory in "$@"; do run "memory-$memory" --memory "$memory"; done
