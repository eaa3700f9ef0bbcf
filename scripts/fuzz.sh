#!/usr/bin/env bash
# Fuzzing beyond the short pass that ctest runs (label "fuzz"). Targets: scenario, suite,
# profile, environment, mjcf, urdf, trials, trajectory, bench (fuzz/fuzz_targets.h); their seed
# inputs are project files and fuzz/seeds/.
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]     default: 60 s per target, every target
#
# With clang (not installed by scripts/setup.sh; `apt-get install clang` on Debian 12 brings
# clang 14 and libFuzzer) it builds build-fuzz/ with libFuzzer, AddressSanitizer and
# UndefinedBehaviorSanitizer and runs each target's fuzz_<target> for SECONDS, keeping its
# corpus in build-fuzz/corpus/<target>/ and any crash in build-fuzz/findings/. Without clang it
# runs the deterministic mutation driver (build/bin/taskmatrix_fuzz) for about as long.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(scenario suite profile environment mjcf urdf trials trajectory bench)
jobs="${TASKMATRIX_JOBS:-2}"

if command -v clang++ >/dev/null && command -v clang >/dev/null; then
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DTASKMATRIX_LIBFUZZER=ON -DTASKMATRIX_BUILD_TESTS=OFF -DTASKMATRIX_BUILD_BENCH=OFF >/dev/null
  cmake --build build-fuzz -j"$jobs" --target taskmatrix_fuzz $(printf 'fuzz_%s ' "${targets[@]}")
  build-fuzz/bin/taskmatrix_fuzz --write-seeds build-fuzz/corpus "${targets[@]}"
  mkdir -p build-fuzz/findings
  export ASAN_OPTIONS="detect_leaks=0:${ASAN_OPTIONS:-}"
  export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:${UBSAN_OPTIONS:-}"
  for t in "${targets[@]}"; do
    corpus="build-fuzz/corpus/$t"  # starts with the target's seed inputs
    echo "fuzz.sh: $t: libFuzzer for $seconds s"
    build-fuzz/bin/fuzz_"$t" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=4096 \
      -artifact_prefix="build-fuzz/findings/$t-" -print_final_stats=1 "$corpus" 2>&1 |
      grep -E "^(stat::number_of_executed_units|stat::new_units_added|==[0-9]+==ERROR|SUMMARY|INFO: Running with)" || true
  done
  ls build-fuzz/findings | grep -q . && { echo "fuzz.sh: findings in build-fuzz/findings/"; exit 1; }
  echo "fuzz.sh: no findings"
else
  cmake --build build -j"$jobs" --target taskmatrix_fuzz
  # The mutation driver runs about 30 light inputs or 8 scene loads per second on one core.
  exec build/bin/taskmatrix_fuzz --budget $((seconds * 30)) --seed "$(date +%s)" \
    --out fuzz-findings "${targets[@]}"
fi
