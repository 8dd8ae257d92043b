#!/usr/bin/env bash
# Benchmark: named scenarios, per stage wall time, peak memory and throughput, plus accuracy.
# Usage: scripts/bench.sh [--quick] [scenario ...]   (writes bench/results.json)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh" >/dev/null
exec python3 "$root/bench/bench.py" --xsect "${XSECT_BUILD_DIR:-$root/build}/xsect" --root "$root" "$@"
