#!/bin/sh
# Issue 28: `vdbmesh mesh` under mpirun gives the same bytes as one plain process, on a phantom
# it writes (a cylinder through five node layers, noisy, so that ranks split it mid-surface), at
# --error 0.25 and at the default error 0 (the dual mesh by bricks).
# The phantom and the plain runs are made once (a ctest fixture) for the runs with 1, 2 and 3 ranks:
#   mesh_under_mpirun.sh plain VDBMESH WORK          writes WORK/cylinder.nii.gz, WORK/plain<error>.ply and .obj
#   mesh_under_mpirun.sh ranks VDBMESH WORK MPIEXEC RANKS [ply|obj]
# The second exits 0 when the files the ranks write together are byte-identical to the plain runs'
# (in that format: binary PLY by default, OBJ's text), and no temporary file is left; else 1.
set -eu
step=$1 vdbmesh=$2 work=$3
mesh="mesh $work/cylinder.nii.gz --iso 0.5 -q"
if [ "$step" = plain ]; then
    mkdir -p "$work"
    "$vdbmesh" phantom cylinder --dims 200,200,600 --radius 80 --noise 0.05 -q -o "$work/cylinder.nii.gz"
    for error in 0.25 0; do
        "$vdbmesh" $mesh --error $error -o "$work/plain$error.ply"
        "$vdbmesh" $mesh --error $error -o "$work/plain$error.obj"
    done
    exit 0
fi
mpiexec=$4 ranks=$5 format=${6:-ply}
output="$work/ranks$ranks.$format"
trap 'rm -f "$output"' EXIT
for error in 0.25 0; do
    # Root may start ranks here (tests run as root), and more ranks than cores.
    "$mpiexec" --allow-run-as-root --oversubscribe -np "$ranks" "$vdbmesh" $mesh --error $error --threads 1 -o "$output"
    if ! cmp "$work/plain$error.$format" "$output"; then
        echo "mesh --error $error under mpirun -np $ranks differs from the plain run ($format)"
        exit 1
    fi
    if ls "$work"/ranks$ranks.$format.tmp-* >/dev/null 2>&1; then
        echo "mesh --error $error under mpirun -np $ranks left a temporary file"
        exit 1
    fi
    echo "mesh --error $error under mpirun -np $ranks: the same $(wc -c <"$work/plain$error.$format") bytes as the plain run ($format)"
done
