#!/usr/bin/env bash
# Quick start: install what is missing, build the library and the `vdbmesh` program (nothing
# else: the tests, benchmarks and Python module are built by scripts/test.sh), then mesh the
# bundled sample (a sphere phantom written by `vdbmesh phantom`) into sample.stl and check it.
set -euo pipefail
cd "$(dirname "$0")/.."
# The first build takes about serial_seconds of CPU time (measured: 622 s of user time for this
# script in a fresh clone without a compiler cache, 5 min 34 s of wall time on 2 cores); ccache
# makes later builds take seconds.
serial_seconds=620
cores=$(nproc)
minutes=$(( (serial_seconds / cores + 59) / 60 ))
step() { printf '\n== %s\n' "$*" >&2; }
cat >&2 <<TEXT
vdbmesh quick start
  1. installs the Debian packages the program needs (only those missing; sudo when not root)
  2. builds the library and the vdbmesh program into build/: about $minutes min on $cores cores the first time
  3. meshes the bundled sample testdata/sphere_phantom.nii.gz into sample.stl and checks it
TEXT
step "1-2. packages and build"
bash scripts/build.sh
step "3. the sample: describe it, mesh it at its isovalue, check the mesh"
build/vdbmesh info testdata/sphere_phantom.nii.gz
build/vdbmesh mesh testdata/sphere_phantom.nii.gz --iso 0.5 -o sample.stl
build/vdbmesh check sample.stl
cat >&2 <<'TEXT'

Done: sample.stl is closed, manifold and free of self-intersections. Try next:
  build/vdbmesh view sample.stl                           # look at it in your browser
  build/vdbmesh info YOUR_SCAN                            # any scan we read: format, spacing, a suggested --iso
  build/vdbmesh mesh YOUR_SCAN --iso ISO -o scan.stl      # then mesh it (README: "Commands")
TEXT
