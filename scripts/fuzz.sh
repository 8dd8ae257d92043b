#!/usr/bin/env bash
# Fuzzes xsect (issue 15, item 2):
#  1. every reader (tests/fuzz/reader_harnesses.cpp) with libFuzzer, built with clang,
#     AddressSanitizer and UndefinedBehaviorSanitizer into ${XSECT_FUZZ_BUILD_DIR:-build-fuzz},
#     starting from the seed corpora in tests/fuzz/corpus/, two readers at a time; prints the
#     executions per reader;
#  2. the geometric fuzzer (tests/geometric_fuzz.h): random degenerate plane sets and sections
#     through `xsect run`, and the configuration fuzzer (tests/test_configuration_fuzz.cpp: random
#     settings, poses, bit depths and destinations), chunks of 50 configurations, one of each at
#     a time.
# A crash, hang (10 s per input), leak or sanitizer report fails the script; its input is left in
# build-fuzz/artifacts/: add it to tests/fuzz/corpus/<reader>/ as crash-<what>, where ctest replays it.
# Usage:
#   scripts/fuzz.sh [SECONDS]                 about SECONDS (default 60): readers 2/3, geometric 1/3
#   scripts/fuzz.sh --readers-only [SECONDS]  readers only
#   scripts/fuzz.sh --ci                      readers only, the same inputs every time: each corpus
#                                             replayed, then 10,000 mutations from seed 1 (6 s at most)
# Building does not count in SECONDS.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
mode=explore
case "${1:-}" in
  --readers-only) mode=readers; shift ;;
  --ci) mode=ci; shift ;;
esac
seconds="${1:-60}"
build="${XSECT_BUILD_DIR:-$root/build}"
fuzzbuild="${XSECT_FUZZ_BUILD_DIR:-$root/build-fuzz}"
"$root/scripts/install-deps.sh"
mkdir -p "$fuzzbuild/logs" "$fuzzbuild/artifacts"
configure=(cmake -S "$root" -B "$fuzzbuild" -G Ninja -DXSECT_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo)
if ! { CC=clang CXX=clang++ "${configure[@]}" && cmake --build "$fuzzbuild" --parallel "$(nproc)"; } \
     > "$fuzzbuild/logs/build.log" 2>&1; then
  tail -40 "$fuzzbuild/logs/build.log"; echo "fuzz: building the harnesses failed" >&2; exit 1
fi

readers=(csl slices config mesh_ply mesh_stl mesh_obj nrrd truth phantom vdb image poses contour plus_mha plus_xml)
if [ "$mode" = explore ]; then reader_seconds=$(( seconds * 2 / 3 )); else reader_seconds=$seconds; fi
per_reader=$(( reader_seconds * 2 / ${#readers[@]} ))
[ "$per_reader" -ge 1 ] || per_reader=1
# The harnesses' scratch files (one folder per process) stay inside the fuzz build.
export TMPDIR="$fuzzbuild/tmp"
rm -rf "$TMPDIR" && mkdir -p "$TMPDIR"
export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=0"
export LSAN_OPTIONS="suppressions=$root/tests/fuzz/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
failed=0
fuzz_reader() {  # one reader; exploration keeps a working corpus that grows across runs
  local r="$1" log="$fuzzbuild/logs/$1.log" work="$fuzzbuild/corpus/$1" limits
  if [ "$mode" = ci ]; then
    work="$fuzzbuild/ci-corpus/$r"; rm -rf "$work"
    limits=(-seed=1 -runs=10000 -max_total_time=6)
  else
    limits=(-max_total_time="$per_reader")
  fi
  mkdir -p "$work"
  # `timeout`: libFuzzer's own limit leaves out the replay of the corpus it starts from.
  (cd "$fuzzbuild" && timeout $(( per_reader * 2 + 300 )) "$fuzzbuild/tests/fuzz/fuzz_$r" "$work" \
     "$root/tests/fuzz/corpus/$r" "${limits[@]}" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
     -artifact_prefix="$fuzzbuild/artifacts/$r-" -print_final_stats=1) > "$log" 2>&1
}
for ((i = 0; i < ${#readers[@]}; i += 2)); do
  pids=(); names=()
  for r in "${readers[@]:i:2}"; do fuzz_reader "$r" & pids+=($!); names+=("$r"); done
  for k in "${!pids[@]}"; do
    r="${names[$k]}"; log="$fuzzbuild/logs/$r.log"
    if wait "${pids[$k]}"; then status=ok; else status=FAILED; failed=$((failed + 1)); fi
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    took=$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$log" | tail -1)
    printf 'reader %-9s %9s executions in %4s s: %s\n' "$r" "${runs:-?}" "${took:-?}" "$status"
    if [ "$status" = FAILED ]; then grep -E "ERROR|SUMMARY|Test unit written" "$log" | head -5 || tail -5 "$log"; fi
  done
done

if [ "$mode" = explore ]; then
  if ! "$root/scripts/build.sh" > "$fuzzbuild/logs/xsect-build.log" 2>&1; then
    tail -40 "$fuzzbuild/logs/xsect-build.log"; echo "fuzz: building xsect failed" >&2; exit 1
  fi
  seed=$(( (RANDOM << 15 | RANDOM) * 1000 ))
  end=$(( $(date +%s) + seconds - reader_seconds ))
  chunks=0; failed_chunks=0
  while [ "$(date +%s)" -lt "$end" ]; do
    pids=()
    for lane in 0 1; do
      # Lane 0 the geometric fuzzer, lane 1 the configuration fuzzer (issue 48). Each run has its
      # own limit (two minutes, one); a chunk of 50 gets 50 of them at most.
      XSECT_FUZZ_SEED=$(( seed + chunks * 50 )) XSECT_FUZZ_CONFIGS=50 \
      XSECT_CONFIG_FUZZ_SEED=$(( seed + chunks * 50 )) XSECT_CONFIG_FUZZ_CONFIGS=50 \
        timeout 6000 "$build/xsect_tests" \
        --gtest_filter="$([ $lane = 0 ] && echo 'Shards/GeometricFuzz.*/0' || echo 'Shards/ConfigurationFuzz.*/0')" \
        > "$fuzzbuild/logs/geometric-lane$lane.log" 2>&1 &
      pids+=($!)
    done
    for lane in 0 1; do
      # A lane passes only when its one test ran and passed (a filter matching nothing passes too).
      if ! wait "${pids[$lane]}" || ! grep -q '^\[  PASSED  \] 1 test' "$fuzzbuild/logs/geometric-lane$lane.log"; then
        failed_chunks=$((failed_chunks + 1)); cat "$fuzzbuild/logs/geometric-lane$lane.log"
      fi
    done
    chunks=$((chunks + 2))
  done
  echo "geometric and configuration fuzz: $((chunks * 50)) configurations from seed $seed, $failed_chunks failing chunks"
  failed=$((failed + failed_chunks))
fi
[ "$failed" -eq 0 ]
