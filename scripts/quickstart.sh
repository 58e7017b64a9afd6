#!/usr/bin/env bash
# Quick start, command 1: installs the Debian packages, builds, and runs the
# main job on the built-in default scene: a synthetic courtyard recording is
# generated and imported into a COLMAP workspace.
# Usage: bash scripts/quickstart.sh [output folder, default ./quickstart]
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-quickstart}"
bash scripts/install_deps.sh
bash scripts/build.sh
if [ ! -f "$out/dataset/calibration.yaml" ]; then
  build/colmap-lidar synthesize --output_path "$out/dataset"
fi
build/colmap-lidar lidar_importer --dataset_path "$out/dataset" \
  --workspace_path "$out/workspace" --LidarImport.overwrite 1
