#!/usr/bin/env bash
# Build the case-file fuzz target with clang (libFuzzer + AddressSanitizer + UBSan) and fuzz
# sph::parse_case / sph::build_system for a while (docs/fuzzing.md).
#
#   tests/fuzz/run.sh [--seconds N] [BUILD_DIR] [-- extra libFuzzer options]
#
# BUILD_DIR (default build-fuzz/ in the repository) gets the build, a working copy of the
# seed corpus (corpus/: the repository's tests/fuzz/corpus is never written) and the
# findings (findings/: crash-*, leak-*, timeout-*, oom-* inputs).
# Exit codes: 0 no finding; 1 a finding or a build failure; 77 clang or libFuzzer is not
# installed (CTest counts the test as skipped; scripts/install-deps.sh installs both).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
seconds=60
build=""
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    --seconds=*) seconds="${1#*=}"; shift ;;
    -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
    --) shift; extra=("$@"); break ;;
    *) build="$1"; shift ;;
  esac
done
[ -n "$build" ] || build="$root/build-fuzz"

cxx="${FUZZ_CXX:-}"
if [ -z "$cxx" ]; then
  for c in clang++ clang++-14 clang++-15 clang++-16; do
    if command -v "$c" >/dev/null; then cxx="$(command -v "$c")"; break; fi
  done
fi
if [ -z "$cxx" ]; then
  echo "fuzz: SKIPPED: clang++ not found (apt-get install clang libclang-rt-14-dev, or scripts/install-deps.sh)"
  exit 77
fi
probe="$(mktemp -d)"
trap 'rm -rf "$probe"' EXIT
echo 'extern "C" int LLVMFuzzerTestOneInput(const unsigned char*, unsigned long) { return 0; }' > "$probe/p.cpp"
if ! "$cxx" -fsanitize=fuzzer,address,undefined "$probe/p.cpp" -o "$probe/p" 2>"$probe/err"; then
  echo "fuzz: SKIPPED: $cxx cannot link libFuzzer with ASan/UBSan (Debian: apt-get install libclang-rt-14-dev):"
  head -5 "$probe/err"
  exit 77
fi

mkdir -p "$build"
build="$(cd "$build" && pwd)"
t0=$(date +%s)
echo "fuzz: building $build/fuzz_case with $cxx"
cmake -S "$here" -B "$build" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE=None >"$build/configure.log" 2>&1 ||
  { cat "$build/configure.log"; echo "fuzz: configure failed"; exit 1; }
cmake --build "$build" -j"$(nproc)" || { echo "fuzz: build failed"; exit 1; }
t1=$(date +%s)

# Work on a copy: the fuzzer adds inputs to its corpus folder. Seeds are re-copied each run
# (new seeds join the inputs grown by earlier runs).
mkdir -p "$build/corpus" "$build/findings"
cp "$here"/corpus/* "$build/corpus/"
before=$(ls "$build/findings" | wc -l)
echo "fuzz: fuzzing for ${seconds} s over $(ls "$build/corpus" | wc -l) inputs (build took $((t1 - t0)) s)"
# ASan returns freed memory to the system (and keeps a smaller quarantine): without it the
# resident size creeps up over a long run towards -rss_limit_mb with no leak at all
export ASAN_OPTIONS="${ASAN_OPTIONS:-allocator_release_to_os_interval_ms=500:quarantine_size_mb=64}"
set +e
# exit codes forced to 1: libFuzzer's default for errors is 77, which CTest would read as "skipped"
"$build/fuzz_case" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=8192 \
  -error_exitcode=1 -timeout_exitcode=1 -dict="$here/case.dict" -artifact_prefix="$build/findings/" \
  -print_final_stats=1 "${extra[@]}" "$build/corpus" 2>"$build/fuzz.log"
rc=$?
set -e
t2=$(date +%s)
grep -E "^(stat::number_of_executed_units|stat::peak_rss_mb|#[0-9]+ +DONE)" "$build/fuzz.log" || true
after=$(ls "$build/findings" | wc -l)
if [ $rc -ne 0 ] || [ "$after" -ne "$before" ]; then
  tail -60 "$build/fuzz.log"
  echo "fuzz: FINDING (libFuzzer exit $rc); inputs in $build/findings/:"
  ls -t "$build/findings" | head
  echo "reproduce: $build/fuzz_case $build/findings/FILE   (docs/fuzzing.md: how to add it to the corpus)"
  exit 1
fi
echo "fuzz: no findings in $((t2 - t1)) s (build $((t1 - t0)) s); log: $build/fuzz.log"
