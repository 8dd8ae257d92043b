#!/usr/bin/env bash
# Installs what is missing, builds (Release), runs every test through ctest, builds the bench's
# baseline, then replays every reader's corpus and fuzzes it briefly with a fixed seed under
# AddressSanitizer and UndefinedBehaviorSanitizer (scripts/fuzz.sh --ci: the same inputs every run).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
build="${XSECT_BUILD_DIR:-$root/build}"
cd "$build"
ctest --output-on-failure --parallel "$(nproc)" --timeout 900
# The bench's Poisson baseline is not in the default build: built here so that it cannot rot.
cmake --build "$build" --target xsect_poisson_baseline
"$root/scripts/fuzz.sh" --ci
