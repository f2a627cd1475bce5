#!/usr/bin/env bash
# Installs what is missing, then configures and builds vdbmesh into build/.
#   build.sh          the library and the `vdbmesh` program only (what the quick start runs)
#   build.sh --all    everything: also the tests, the benchmarks and the Python module
set -euo pipefail
cd "$(dirname "$0")/.."
everything=OFF
case "${1:-}" in
  --all) everything=ON ;;
  "") ;;
  *) echo "usage: build.sh [--all]" >&2; exit 2 ;;
esac
if [ $everything = ON ]; then bash scripts/install-deps.sh --tests; else bash scripts/install-deps.sh; fi
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
# Configure once; again only to switch the tests, benchmarks and Python module on (a quick
# start's build/ then grows into the full one, keeping what it compiled).
if ! grep -qs "^VDBMESH_BUILD_TESTS:BOOL=$everything\$" build/CMakeCache.txt && { [ $everything = ON ] || [ ! -f build/CMakeCache.txt ]; }; then
  cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DVDBMESH_BUILD_TESTS=$everything \
        -DVDBMESH_BUILD_BENCH=$everything -DVDBMESH_BUILD_PYTHON=$everything >&2
fi
if [ $everything = ON ]; then
  cmake --build build --parallel "$(nproc)" >&2
else
  cmake --build build --parallel "$(nproc)" --target vdbmesh >&2
fi
