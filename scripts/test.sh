#!/usr/bin/env bash
# Fresh machine -> green test suite: install dependencies, build, run unit tests and the coarse
# validation cases through CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh --tests
scripts/build.sh
cd build
# the suite's ParaView round trip must run, not skip (install-deps --tests installed pvpython)
export SPHFLUME_REQUIRE_PARAVIEW=1
# as many tests at once as cores: the checks run one thread each (CMakeLists.txt), the tests that run two threads or
# two ranks take two slots (PROCESSORS)
ctest --output-on-failure -j "$(nproc)" "$@"
