#!/usr/bin/env bash
# Example Slurm batch script (issue 19, docs/scale.md): the whole pipeline
# of one recording, with the per-image stage (PatchMatch) on every allocated
# core of every node and the other stages in one process on the first node.
# The workspace must be on a filesystem that every node mounts at the same
# path; rank 0 alone opens its database.db.
#
#   sbatch --nodes=4 --ntasks-per-node=2 scripts/cluster/slurm_dense.sh \
#     DATASET WORKSPACE
#
# DATASET: a rig dataset (docs/dataset-format.md); WORKSPACE: the workspace
# to create or resume. COLMAP_LIDAR_BIN overrides the colmap-lidar binary
# (default: colmap-lidar on PATH). Every stage resumes: resubmitting after a
# failure or a time limit continues where the job stopped.
#SBATCH --job-name=colmap-lidar
#SBATCH --cpus-per-task=1
#SBATCH --time=12:00:00
set -euo pipefail

if [[ $# -ne 2 ]]; then
  echo "usage: sbatch [slurm options] $0 DATASET WORKSPACE" >&2
  exit 2
fi
DATASET=$1
WORKSPACE=$2
BIN=${COLMAP_LIDAR_BIN:-colmap-lidar}
THREADS=${SLURM_CPUS_PER_TASK:-1}
NODE_CORES=${SLURM_CPUS_ON_NODE:-$(nproc)}

# 1. One process: import, sfm (features, matching, lidar_mapper with its line
#    extraction), dense (undistortion and LIDAR fusion).
srun --nodes=1 --ntasks=1 --cpus-per-task="${NODE_CORES}" \
  "${BIN}" automatic_reconstructor --workspace_path "${WORKSPACE}" \
  --dataset_path "${DATASET}" --AutomaticReconstruction.stages :dense \
  --AutomaticReconstruction.num_threads "${NODE_CORES}"

# 2. Every task: PatchMatch, each rank its share of the references (the
#    same maps as one process; docs/scale.md).
srun "${BIN}" lidar_patch_match_stereo \
  --workspace_path "${WORKSPACE}/dense" \
  --LidarPatchMatch.num_threads "${THREADS}"

# 3. One process: the rest. The pipeline's patch_match stage finds every
#    map written above and skips it; then fusion, mesh, evaluate, report.
srun --nodes=1 --ntasks=1 --cpus-per-task="${NODE_CORES}" \
  "${BIN}" automatic_reconstructor --workspace_path "${WORKSPACE}" \
  --dataset_path "${DATASET}" --AutomaticReconstruction.stages patch_match: \
  --AutomaticReconstruction.num_threads "${NODE_CORES}"
