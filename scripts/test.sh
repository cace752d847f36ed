#!/usr/bin/env bash
# Fresh machine -> green test suite: install dependencies, build, run unit tests and the coarse
# validation cases through CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
cd build
ctest --output-on-failure -j 1 "$@"
