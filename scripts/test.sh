#!/usr/bin/env bash
# Installs what is missing, builds (Release), runs every test through ctest, then replays every
# reader's corpus and fuzzes it briefly with a fixed seed under AddressSanitizer and
# UndefinedBehaviorSanitizer (scripts/fuzz.sh --ci: the same inputs every run). The bench's Poisson
# baseline is built by scripts/bench.sh, which uses it (here it cost CI time for no test).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
build="${XSECT_BUILD_DIR:-$root/build}"
cd "$build"
ctest --output-on-failure --parallel "$(nproc)" --timeout 900
"$root/scripts/fuzz.sh" --ci
