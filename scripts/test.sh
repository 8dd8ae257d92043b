#!/usr/bin/env bash
# Installs what is missing, builds (Release), runs every test through ctest, then fuzzes every
# reader briefly under AddressSanitizer and UndefinedBehaviorSanitizer (scripts/fuzz.sh).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
build="${XSECT_BUILD_DIR:-$root/build}"
cd "$build"
ctest --output-on-failure --parallel "$(nproc)" --timeout 900
"$root/scripts/fuzz.sh" --readers-only 60
