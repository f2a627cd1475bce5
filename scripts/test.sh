#!/usr/bin/env bash
# Runs the whole test suite (installs and builds first when needed).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
cd build
ctest --output-on-failure --parallel "$(nproc)"
