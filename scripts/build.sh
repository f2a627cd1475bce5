#!/usr/bin/env bash
# Installs what is missing, then configures and builds vdbmesh into build/.
#   build.sh          the library and the `vdbmesh` program only (what the quick start runs)
#   build.sh --tests  also the tests, the Python module and MPI (what scripts/test.sh runs)
#   build.sh --all    also the benchmarks (bench/)
set -euo pipefail
cd "$(dirname "$0")/.."
tests=OFF bench=OFF
case "${1:-}" in
  --tests) tests=ON ;;
  --all) tests=ON bench=ON ;;
  "") ;;
  *) echo "usage: build.sh [--tests | --all]" >&2; exit 2 ;;
esac
if [ $bench = ON ]; then bash scripts/install-deps.sh --all
elif [ $tests = ON ]; then bash scripts/install-deps.sh --tests
else bash scripts/install-deps.sh
fi
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
# Configure once; again only to switch the tests (with the Python module and MPI) or the
# benchmarks on (a quick start's build/ then grows into the full one, keeping what it compiled).
# Nothing is switched off: a build/ with the benchmarks keeps building them.
is_on() { grep -qs "^$1:BOOL=ON\$" build/CMakeCache.txt; }
if [ ! -f build/CMakeCache.txt ] || { [ $tests = ON ] && ! is_on VDBMESH_BUILD_TESTS; } || { [ $bench = ON ] && ! is_on VDBMESH_BUILD_BENCH; }; then
  is_on VDBMESH_BUILD_BENCH && bench=ON
  cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DVDBMESH_BUILD_TESTS=$tests \
        -DVDBMESH_BUILD_BENCH=$bench -DVDBMESH_BUILD_PYTHON=$tests -DVDBMESH_MPI=$tests >&2
fi
if [ $tests = ON ]; then
  cmake --build build --parallel "$(nproc)" >&2
else
  cmake --build build --parallel "$(nproc)" --target vdbmesh >&2
fi
