#!/usr/bin/env bash
# Install SPHFlume's build and run dependencies from Debian 12 packages. Idempotent: packages
# already installed are left as they are. Needs root (or sudo).
#
#   scripts/install-deps.sh           build, run, validation scripts
#   scripts/install-deps.sh --tests   the same plus what only the test suite needs (ParaView's
#                                     pvpython for the XDMF round trip; ~450 MB, scripts/test.sh)
#   scripts/install-deps.sh --bench   the same plus the peers the benchmarks run (PySPH: bench/isph_vs_pysph.py)
set -euo pipefail
PKGS=(
  build-essential g++ cmake make pkg-config git
  libeigen3-dev libmuparser-dev libyaml-cpp-dev libhdf5-dev libcli11-dev libfmt-dev libspdlog-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libhypre-dev libopenmpi-dev openmpi-bin libhdf5-openmpi-dev
  libcgal-dev ffmpeg
  python3 python3-numpy python3-matplotlib python3-h5py python3-yaml
  clang libclang-rt-14-dev
)
if [ "${1:-}" = "--tests" ]; then
  PKGS+=(paraview python3-paraview)
fi
if [ "${1:-}" = "--bench" ]; then
  PKGS+=(python3-pysph)
fi
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PKGS[@]} packages already installed"
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
