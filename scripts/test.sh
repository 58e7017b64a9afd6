#!/usr/bin/env bash
# Quick start, command 2: installs the Debian packages, builds, and runs the
# whole test suite with CTest. Tests read the KITTI sample in ../shared.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
cd build
ctest --output-on-failure -j"$(nproc)" --timeout 900
