#!/usr/bin/env bash
# Installs the Debian 12 packages vdbmesh needs, only those that are missing.
#   install-deps.sh          what the library and the `vdbmesh` program need (the quick start)
#   install-deps.sh --tests  that and what the tests, MPI and the Python module need (CI's, scripts/test.sh's)
#   install-deps.sh --all    that and what only the benchmarks need (bench/: build.sh --all)
set -euo pipefail
packages=(
  cmake g++ ninja-build ccache pkg-config
  libopenvdb-dev libtbb-dev libblosc-dev
  libboost-dev libboost-iostreams-dev   # OpenVDB's CMake module fails without them
  libeigen3-dev zlib1g-dev libgdcm-dev libcli11-dev nlohmann-json3-dev
  libnanoflann-dev                      # the k-d tree of the points stage (src/points, header-only)
  libcpp-httplib-dev                    # the server of `vdbmesh view`
)
# Node.js and npm build the page of `vdbmesh view` (web/: npm ci, esbuild); Debian's, unless the machine has its own.
command -v node >/dev/null || packages+=(nodejs)
command -v npm >/dev/null || packages+=(npm)
if [ "${1:-}" = "--tests" ] || [ "${1:-}" = "--all" ]; then
  packages+=(
    libgtest-dev
    libopenvdb-tools                      # vdb_print: the tests open our .vdb files with OpenVDB's own tool
    libcgal-dev   # test-only: the independent judge of the mesh guarantees (tests/common/cgal_judge.cpp)
    chromium chromium-driver              # the browser test of the page (headless, WebGL through SwiftShader)
    pybind11-dev python3-dev python3-numpy python3-pytest   # the Python module and its tests
    python3-skimage                                          # its comparison tests and bench/python_vs_skimage.py
    libopenmpi-dev openmpi-bin            # VDBMESH_MPI=ON (the test build): vdbmesh distributed under mpirun (issue 28, src/ranks)
  )
elif [ -n "${1:-}" ]; then
  echo "usage: install-deps.sh [--tests | --all]" >&2
  exit 2
fi
# Only the benchmarks use these: on a fresh Debian 12 they are 43 more packages (45 MB to fetch,
# 224 MB unpacked, mostly VTK's), which CI's test run (--tests) need not install.
if [ "${1:-}" = "--all" ]; then
  packages+=(
    libmeshoptimizer-dev                  # bench/decimate_bench.cpp: the speed reference of vdbmesh mesh --decimate
    python3-vtk9                          # bench/labels_vs_vtk.py: VTK discrete flying edges + windowed sinc, the reference of mesh --labels
  )
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "Installing: ${missing[*]}" >&2
sudo_cmd=()
[ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
"${sudo_cmd[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
