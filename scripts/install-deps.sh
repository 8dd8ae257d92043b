#!/usr/bin/env bash
# Installs the Debian packages xsect builds and runs with (only what is missing).
# --browser also installs Chromium, which only the real-browser test of report.html needs
# (tests/test_report_browser.cpp; headless, WebGL through its bundled SwiftShader).
set -euo pipefail
browser=0
for a in "$@"; do
  case "$a" in
    --browser) browser=1 ;;
    *) echo "usage: $0 [--browser]" >&2; exit 2 ;;
  esac
done
PKGS=(build-essential cmake ninja-build pkg-config libcgal-dev libopencv-dev libopenvdb-dev
      libboost-iostreams-dev libtbb-dev libyaml-cpp-dev libeigen3-dev libgtest-dev libbenchmark-dev
      nlohmann-json3-dev libcli11-dev zlib1g-dev libssl-dev python3
      libpugixml-dev  # PLUS device-set XML (io/plus_device_set)
      libceres-dev  # pose correction's robust least squares (geometry/conformity/pose_correction)
      libgudhi-dev  # persistence of handles and cavities (geometry/reconstruction/topology_features)
      libjs-three  # three.js, inlined into report.html's 3D view
      graphviz  # dot: the connectivity graph as inline SVG in report.html
      clang libclang-rt-dev  # clang + its runtimes: libFuzzer, ASan, UBSan (scripts/fuzz.sh)
      pybind11-dev python3-dev python3-numpy python3-pytest  # the Python module (pipeline/python/)
      snakemake)  # the cohort workflow (workflows/cohort/)
if [ "$browser" -eq 1 ]; then PKGS+=(chromium); fi  # headless browser test of report.html
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}" >&2
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
