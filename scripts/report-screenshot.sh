#!/usr/bin/env bash
# Makes README.md's picture, docs/images/report.png: the report page of the demo's run
# (scripts/demo.sh: configs/phantoms/torus-demo.yaml) as headless Chromium shows it in a 1400x900
# window. Needs the built tool and Chromium (scripts/install-deps.sh --browser).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
xsect="${XSECT_BUILD_DIR:-$root/build}/xsect"
command -v chromium >/dev/null || { echo "chromium is missing: scripts/install-deps.sh --browser" >&2; exit 2; }
[ -x "$xsect" ] || { echo "$xsect is missing: scripts/build.sh xsect" >&2; exit 2; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$xsect" phantom "$root/configs/phantoms/torus-demo.yaml" --out "$work/torus" --quiet
"$xsect" run "$work/torus/config.yaml" --out "$work/result" --quiet
mkdir -p "$root/docs/images"
# Software WebGL (SwiftShader); without GLIBC_TUNABLES, which breaks it (tests/test_report_browser.cpp).
env -u GLIBC_TUNABLES timeout 120 chromium --headless --no-sandbox --disable-gpu-sandbox \
  --enable-unsafe-swiftshader --use-angle=swiftshader --window-size=1400,900 --force-device-scale-factor=1 \
  --hide-scrollbars --user-data-dir="$work/profile" --no-first-run --virtual-time-budget=5000 \
  --screenshot="$root/docs/images/report.png" "file://$work/result/report.html" >/dev/null 2>&1
echo "written: $root/docs/images/report.png"
