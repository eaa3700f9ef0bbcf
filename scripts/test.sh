#!/usr/bin/env bash
# README command 2: install what is missing, build Release with warnings as errors, run
# every test with ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh -DTASKMATRIX_WERROR=ON
cd build
ctest --output-on-failure -j"${TASKMATRIX_JOBS:-2}" --timeout 300
