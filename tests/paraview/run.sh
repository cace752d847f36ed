#!/usr/bin/env bash
# ParaView round trip: make a short dam-break run and check, with ParaView's own XDMF reader
# (pvpython), that particles.xdmf + snapshots/*.h5 read back correctly.
#
#   tests/paraview/run.sh [path/to/sphflume]      (default: build/sphflume)
#
# Needs pvpython (Debian/Ubuntu: apt-get install paraview python3-paraview; or set PVPYTHON).
# Exits 77 (skip) when pvpython is missing (1 with SPHFLUME_REQUIRE_PARAVIEW=1, as scripts/test.sh sets), 0 on pass, non-zero on failure. No X display is
# needed: the check only reads data, nothing is rendered. KEEP=1 keeps the run folder.
set -u
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)

bin=${1:-$root/build/sphflume}
case "$bin" in /*) ;; *) bin="$PWD/$bin" ;; esac

pvpython=${PVPYTHON:-$(command -v pvpython || true)}
if [ -z "$pvpython" ] || [ ! -x "$pvpython" ]; then
  if [ "${SPHFLUME_REQUIRE_PARAVIEW:-0}" = 1 ]; then
    echo "FAIL: pvpython not found and SPHFLUME_REQUIRE_PARAVIEW=1 (scripts/test.sh installs it: scripts/install-deps.sh --tests)"
    exit 1
  fi
  echo "SKIP: pvpython not found (install paraview + python3-paraview, or set PVPYTHON=/path/to/pvpython)"
  exit 77
fi
if [ ! -x "$bin" ]; then
  echo "FAIL: sphflume binary '$bin' not found or not executable"
  exit 1
fi

tmp=$(mktemp -d "${TMPDIR:-/tmp}/sphflume-paraview.XXXXXX")
out="$tmp/out"
cleanup() { if [ "${KEEP:-0}" = 1 ]; then echo "run folder kept: $out"; else rm -rf "$tmp"; fi; }
trap cleanup EXIT

cd "$root" || exit 1
if ! "$bin" run cases/dambreak_2d.yaml -o "$out" -q \
      --set particles.dx=0.0146 --set time.end=0.1 --set time.output_interval=0.05; then
  echo "FAIL: sphflume run failed"
  exit 1
fi

"$pvpython" "$here/read_run.py" "$out"
rc=$?
[ $rc -ne 0 ] && [ "${KEEP:-0}" != 1 ] && echo "(rerun with KEEP=1 to keep the output folder)"
exit $rc
