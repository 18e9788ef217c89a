#!/usr/bin/env bash
# Installs the Debian 12 packages skred needs to build, test and run (as root).
set -euo pipefail
# python3-matplotlib (with python3-numpy, python3-pil): `skred render` / `skred report`;
# chromium: the test that opens the HTML report headless.
pkgs=(cmake make g++ libeigen3-dev libtomlplusplus-dev libcli11-dev libfmt-dev libgtest-dev
      python3-vtk9 python3-numpy python3-matplotlib python3-pil chromium)
missing=()
for p in "${pkgs[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
if [ ${#missing[@]} -gt 0 ]; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -q
  apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
