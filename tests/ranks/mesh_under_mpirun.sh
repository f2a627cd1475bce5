#!/bin/sh
# Issue 28: `vdbmesh mesh` under mpirun gives the same bytes as one plain process, on a phantom
# it writes (a cylinder through five node layers, noisy, so that ranks split it mid-surface), at
# --error 0.25 and at the default error 0 (Marching Cubes by bricks).
# The phantom and the plain run are made once (a ctest fixture) for the runs with 1, 2 and 3 ranks:
#   mesh_under_mpirun.sh plain VDBMESH WORK          writes WORK/cylinder.nii.gz, WORK/plain0.25.ply and WORK/plain0.ply
#   mesh_under_mpirun.sh ranks VDBMESH WORK MPIEXEC RANKS
# The second exits 0 when the files rank 0 writes are byte-identical to the plain runs', else 1.
set -eu
step=$1 vdbmesh=$2 work=$3
mesh="mesh $work/cylinder.nii.gz --iso 0.5 -q"
if [ "$step" = plain ]; then
    mkdir -p "$work"
    "$vdbmesh" phantom cylinder --dims 200,200,600 --radius 80 --noise 0.05 -q -o "$work/cylinder.nii.gz"
    for error in 0.25 0; do "$vdbmesh" $mesh --error $error -o "$work/plain$error.ply"; done
    exit 0
fi
mpiexec=$4 ranks=$5
output="$work/ranks$ranks.ply"
trap 'rm -f "$output"' EXIT
for error in 0.25 0; do
    # Root may start ranks here (tests run as root), and more ranks than cores.
    "$mpiexec" --allow-run-as-root --oversubscribe -np "$ranks" "$vdbmesh" $mesh --error $error --threads 1 -o "$output"
    if ! cmp "$work/plain$error.ply" "$output"; then
        echo "mesh --error $error under mpirun -np $ranks differs from the plain run"
        exit 1
    fi
    echo "mesh --error $error under mpirun -np $ranks: the same $(wc -c <"$work/plain$error.ply") bytes as the plain run"
done
