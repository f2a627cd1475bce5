#!/usr/bin/env bash
# Quick start: install, build, and mesh the bundled sample into sample.stl.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
build/vdbmesh info testdata/sphere_phantom.nii.gz
build/vdbmesh convert testdata/sphere_phantom.nii.gz --iso 0.5 -o sample.vdb
echo "wrote sample.vdb"
