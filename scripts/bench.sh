#!/usr/bin/env bash
# Benchmark: named scenarios, per stage wall time, peak memory and throughput, plus accuracy, with
# CGAL's Poisson surface reconstruction on the same contour points as a baseline row.
# Usage: scripts/bench.sh [--quick] [--no-poisson] [scenario ...]   (writes bench/results.json)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${XSECT_BUILD_DIR:-$root/build}"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh" >/dev/null
# The baseline is not part of the default build (EXCLUDE_FROM_ALL): build it here, unless skipped.
poisson=(--poisson "$build/xsect_poisson_baseline")
if [[ " $* " == *" --no-poisson "* ]]; then
  poisson=()
else
  cmake --build "$build" --target xsect_poisson_baseline >/dev/null
fi
exec python3 "$root/bench/bench.py" --xsect "$build/xsect" "${poisson[@]}" --root "$root" "$@"
