#!/usr/bin/env bash
# Quick start, command 1: installs the Debian packages, builds the
# command-line tool, and runs the main job on the built-in default scene:
# automatic_reconstructor generates the synthetic courtyard recording
# (<out>/dataset), imports it, refines the poses with points and LIDAR lines,
# runs the LIDAR-initialised PatchMatch, fuses, meshes, evaluates against the
# ground truth and writes <out>/report/index.html. Re-running resumes.
# Usage: bash scripts/quickstart.sh [output folder, default ./quickstart]
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-quickstart}"
bash scripts/install_deps.sh
COLMAP_LIDAR_BUILD_TARGET=colmap-lidar bash scripts/build.sh
build/colmap-lidar automatic_reconstructor --workspace_path "$out"
echo "quickstart: mesh $out/dense/meshed-delaunay.ply, report $out/report/index.html"
