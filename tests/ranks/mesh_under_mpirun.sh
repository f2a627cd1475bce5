#!/bin/sh
# Issue 28: `vdbmesh mesh` under mpirun gives the same bytes as one plain process, on a phantom
# it writes (a cylinder through five node layers, noisy, so that ranks split it mid-surface).
# Usage: mesh_under_mpirun.sh MPIEXEC VDBMESH RANKS
# Exit 0 when the file rank 0 writes is byte-identical to the plain run's, else 1.
set -eu
mpiexec=$1 vdbmesh=$2 ranks=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$vdbmesh" phantom cylinder --dims 200,200,600 --radius 80 --noise 0.05 -q -o "$work/cylinder.nii.gz"
mesh="mesh $work/cylinder.nii.gz --iso 0.5 --error 0.25 -q"
"$vdbmesh" $mesh -o "$work/plain.ply"
# Root may start ranks here (tests run as root), and more ranks than cores.
"$mpiexec" --allow-run-as-root --oversubscribe -np "$ranks" "$vdbmesh" $mesh --threads 1 -o "$work/ranks.ply"
if ! cmp "$work/plain.ply" "$work/ranks.ply"; then
    echo "mesh under mpirun -np $ranks differs from the plain run"
    exit 1
fi
echo "mesh under mpirun -np $ranks: the same $(wc -c <"$work/plain.ply") bytes as the plain run"
