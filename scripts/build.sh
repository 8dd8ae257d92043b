#!/usr/bin/env bash
# Configures and builds xsect (Release) into ${XSECT_BUILD_DIR:-build}: every target, or the ones
# named (scripts/build.sh xsect: the tool alone, as scripts/demo.sh does). Ninja shows its progress.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${XSECT_BUILD_DIR:-$root/build}"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build "$build" --parallel "$(nproc)" "${targets[@]}"
# The Python module (docs/python.md), when it was built: where Python finds it.
if [ -f "$build/python/xsect/__init__.py" ] && ls "$build"/python/xsect/_xsect*.so >/dev/null 2>&1; then
  echo "Python: export PYTHONPATH=$build/python   (then: /usr/bin/python3 -c 'import xsect')"
fi
