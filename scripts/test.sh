#!/usr/bin/env bash
# Runs the whole test suite (installs and builds first when needed).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh --tests
cd build
ctest --output-on-failure --parallel "$(nproc)"
# The Python module's tests, run by the interpreter it was built for (none: built without it).
python=$(sed -n 's/^Python3_EXECUTABLE:[A-Z]*=//p' CMakeCache.txt)
if [ -n "$python" ]; then
  PYTHONPATH=python PYTHONDONTWRITEBYTECODE=1 "$python" -m pytest -q -p no:cacheprovider ../python/tests
fi
