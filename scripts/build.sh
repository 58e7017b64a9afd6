#!/usr/bin/env bash
# Configures and builds colmap-lidar in ./build (Release). Usage:
#   bash scripts/build.sh [extra cmake args]
# COLMAP_LIDAR_BUILD_TARGET=colmap-lidar builds only the command-line tool
# (the quick start's run needs no tests or benchmarks); default: everything.
set -euo pipefail
cd "$(dirname "$0")/.."
target="${COLMAP_LIDAR_BUILD_TARGET:-all}"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@" > build.log 2>&1 || { cat build.log; exit 1; }
cmake --build build -j"$(nproc)" --target "$target" >> build.log 2>&1 || { tail -n 80 build.log; exit 1; }
echo "build: ok (build/colmap-lidar, target $target)"
