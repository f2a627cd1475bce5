#!/usr/bin/env bash
# Issue 29's figures from one run (bench/README.md, "Issue 29: the meshers' figures from one run"):
#   1. `compare` on the bunny, CThead, engine and walnut at every error and adaptivity the issue names
#      (the budget rows come by default), the bunny's whole report timed;
#   2. `compare --phantom` on the aligned and tilted cube, cube minus sphere and the cylinder (the
#      `--sharp` rows come by default on a phantom);
#   3. `compare` on the quick start's sample at error 0 against adaptivity 0;
#   4. which volumeToMesh mesh a mesh of ours dominates (each report's own verdict, tabled by
#      bench/dominance.py over 1 and 3);
#   5. what issue 9 met and must still hold: the 1024^3 sphere at error 0.25 (at most 1/150 of
#      error 0's triangles, within 0.5 voxel of the exact sphere: `compare --phantom`),
#      1-thread / 2-thread scaling (vdbmesh_bench), and the bunny's peak memory at error 0.25
#      against volumeToMesh's at 0.25 (`/usr/bin/time -f %M`, one process each).
# Usage: [SAMPLES=N] bench/mesher_figures.sh OUTDIR   (build/ must hold vdbmesh and bench/vdbmesh_bench;
#        the scans are read from $VDBMESH_DATA_DIR, else ../shared/data)
# Run it on a quiet machine: the times are compared within the run, but not across loads.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: bench/mesher_figures.sh OUTDIR}
mkdir -p "$out"
vdbmesh=build/vdbmesh
data=${VDBMESH_DATA_DIR:-../shared/data}
threads=2
samples=${SAMPLES:-100000}  # compare's default; SAMPLES=1000000 for the steadier maxima (bench/README.md)

convert_scans() {
    local bunny=$data/raw_stanford_ct_bunny/bunny_ct_512x512x361_uint16be
    "$vdbmesh" convert --raw-dims 512,512,361 --raw-type i16 --raw-endian big --iso 1200.5 -q \
        "$bunny.part1of2.raw.gz" "$bunny.part2of2.raw.gz" -o "$out/bunny.vdb"
    "$vdbmesh" convert --raw-dims 256,256,113 --raw-type i16 --raw-endian big --iso 600.5 -q \
        "$data/raw_stanford_cthead/CThead_256x256x113_int16be.raw.gz" -o "$out/cthead.vdb"
    "$vdbmesh" convert --iso 100.5 -q "$data/nifti_engine_ct/engine.nii.gz" -o "$out/engine.vdb"
    "$vdbmesh" convert --iso 4084.5 -q "$data/openqvis_walnut_ct/walnut.dat" -o "$out/walnut.vdb"
}

compare_scans() {
    for scan in bunny cthead engine walnut; do
        /usr/bin/time -f "$scan report: %e s elapsed" -a -o "$out/report_seconds.txt" \
            "$vdbmesh" compare "$out/$scan.vdb" --error 0,0.1,0.25,0.5,1,2 --adaptivity 0,0.1,0.25,1 \
            --threads $threads --samples "$samples" -q --json "$out/$scan.json" > "$out/$scan.txt"
    done
}

compare_phantoms() {
    for phantom in cube rotated-cube cube-minus-sphere cylinder; do
        "$vdbmesh" compare --phantom $phantom --size 128 --error 0,0.1 --adaptivity 0 --threads $threads -q \
            --json "$out/phantom_$phantom.json" > "$out/phantom_$phantom.txt"
    done
    "$vdbmesh" compare --phantom sphere --size 1024 --error 0,0.25 --adaptivity 0.25 --no-budget \
        --threads $threads -q --json "$out/phantom_sphere_1024.json" > "$out/phantom_sphere_1024.txt"
    "$vdbmesh" compare testdata/sphere_phantom.nii.gz --iso 0.5 --error 0 --adaptivity 0 --threads $threads -q \
        --json "$out/sample.json" > "$out/sample.txt"
}

peak_memory() {
    : > "$out/peak_kb.txt"
    /usr/bin/time -f "dc error 0.25: %M KB" -a -o "$out/peak_kb.txt" \
        "$vdbmesh" mesh "$out/bunny.vdb" --error 0.25 --threads $threads -q -o "$out/bunny_dc.ply"
    /usr/bin/time -f "openvdb adaptivity 0.25: %M KB" -a -o "$out/peak_kb.txt" \
        "$vdbmesh" mesh "$out/bunny.vdb" --method openvdb --adaptivity 0.25 --threads $threads -q \
        -o "$out/bunny_openvdb.ply"
    rm -f "$out/bunny_dc.ply" "$out/bunny_openvdb.ply"
}

: > "$out/report_seconds.txt"
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)" > "$out/load.txt"
convert_scans
compare_scans
compare_phantoms
python3 bench/dominance.py "$out"/{bunny,cthead,engine,walnut,sample}.json > "$out/dominance.md" || true
peak_memory
build/bench/vdbmesh_bench --scans bunny,cthead,engine,walnut --phantom-sizes 0 --errors 0,0.25,1 \
    --adaptivities 0,0.25,1 --threads 1,2 > "$out/bench.md"
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)" >> "$out/load.txt"
cat "$out/dominance.md" "$out/report_seconds.txt" "$out/peak_kb.txt" "$out/load.txt"
