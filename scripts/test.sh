#!/usr/bin/env bash
# Installs what is missing, builds (Release), runs every test through ctest (the ten slowest
# printed after them), then replays every reader's corpus and fuzzes it briefly with a fixed seed
# under AddressSanitizer and UndefinedBehaviorSanitizer (scripts/fuzz.sh --ci: the same inputs
# every run). The bench's Poisson baseline is built by scripts/bench.sh, which uses it (here it
# cost CI time for no test).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
build="${XSECT_BUILD_DIR:-$root/build}"
cd "$build"
log="$build/Testing/ctest-output.txt"
mkdir -p "$(dirname "$log")"
status=0
ctest --output-on-failure --parallel "$(nproc)" --timeout 900 | tee "$log" || status=$?
# The ten slowest tests, from ctest's own lines ("  12/475 Test  #12: Name .....   Passed   3.21 sec").
echo "The ten slowest tests (seconds):"
# (awk reads to the end: `head` would close the pipe early, and pipefail would end the script.)
sed -n 's/^ *[0-9]*\/[0-9]* Test *#[0-9]*: \([^ ]*\) .* \([0-9.]*\) sec$/\2 \1/p' "$log" | sort -rn |
  awk 'NR <= 10 {printf "  %8.1f  %s\n", $1, $2}'
[ "$status" -eq 0 ] || exit "$status"
"$root/scripts/fuzz.sh" --ci
