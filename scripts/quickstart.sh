#!/usr/bin/env bash
# Fresh machine -> a dam break you can open in ParaView: install dependencies, build, run the
# default case (cases/dambreak_2d.yaml, coarse: a few seconds on 2 cores once built).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
out="${1:-output/dambreak_2d}"
build/sphflume run cases/dambreak_2d.yaml --output "$out" --set particles.dx=0.0073 --set time.end=0.6
echo
echo "Pictures (python/sphflume: the last snapshot, fluid coloured by pressure, walls grey; every gauge):"
PYTHONPATH=python /usr/bin/python3 -m sphflume plot "$out"
echo
echo "Done. Open $out/particles.xdmf in ParaView (File > Open, Xdmf3ReaderS), or read the run in Python:"
echo "  PYTHONPATH=python python3 -c 'import sphflume; print(sphflume.Run(\"$out\").summary)'  (docs/output.md)"
echo "Gauges (CSV): $out/gauges/   Run summary: $out/summary.json"
