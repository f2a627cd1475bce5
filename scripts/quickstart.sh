#!/usr/bin/env bash
# Quick start: install what is missing, build, then mesh the bundled sample (a sphere
# phantom written by `vdbmesh phantom`) into sample.stl and check it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
build/vdbmesh info testdata/sphere_phantom.nii.gz
build/vdbmesh mesh testdata/sphere_phantom.nii.gz --iso 0.5 -o sample.stl
build/vdbmesh check sample.stl
