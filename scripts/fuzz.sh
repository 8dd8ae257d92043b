#!/usr/bin/env bash
# Runs the geometric fuzzer (tests/geometric_fuzz.h) for about SECONDS seconds (default 60):
# random degenerate plane sets and sections through `xsect run`, chunks of 50 configurations from a
# random first seed, two chunks at a time. Every run must exit 0 with a watertight mesh or exit 2
# with a message; a failing configuration is printed with its seed (rerun it with
# XSECT_FUZZ_SEED=<seed> XSECT_FUZZ_CONFIGS=1). Usage: scripts/fuzz.sh [SECONDS]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${XSECT_BUILD_DIR:-$root/build}"
seconds="${1:-60}"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh" >/dev/null
seed=$(( (RANDOM << 15 | RANDOM) * 1000 ))
end=$(( $(date +%s) + seconds ))
chunks=0; failed=0
while [ "$(date +%s)" -lt "$end" ]; do
  pids=()
  for lane in 0 1; do
    # Each run has its own two-minute limit (tests/cli.h); a chunk of 50 gets 50 of them at most.
    XSECT_FUZZ_SEED=$(( seed + (chunks + lane) * 50 )) XSECT_FUZZ_CONFIGS=50 \
      timeout 6000 "$build/xsect_tests" --gtest_filter='Shards/GeometricFuzz.*/0' \
      > "$build/fuzz-lane$lane.log" 2>&1 &
    pids+=($!)
  done
  for lane in 0 1; do
    # A lane passes only when its one test ran and passed (a filter matching nothing passes too).
    if ! wait "${pids[$lane]}" || ! grep -q '^\[  PASSED  \] 1 test' "$build/fuzz-lane$lane.log"; then
      failed=$((failed + 1)); cat "$build/fuzz-lane$lane.log"
    fi
  done
  chunks=$((chunks + 2))
done
echo "geometric fuzz: $((chunks * 50)) configurations from seed $seed, $failed failing chunks"
[ "$failed" -eq 0 ]
