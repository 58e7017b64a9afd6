#!/usr/bin/env bash
# Example Slurm batch script (issue 19, docs/scale.md): the whole pipeline
# of one recording, with the per-image stage (PatchMatch) on every allocated
# core of every node, the mesh's tiles on one task per node, and the other
# stages in one process on the first node.
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

# 3. One process: the depth-map fusion (the pipeline's patch_match stage
#    finds every map written above and skips it).
srun --nodes=1 --ntasks=1 --cpus-per-task="${NODE_CORES}" \
  "${BIN}" automatic_reconstructor --workspace_path "${WORKSPACE}" \
  --dataset_path "${DATASET}" --AutomaticReconstruction.stages patch_match:fusion \
  --AutomaticReconstruction.num_threads "${NODE_CORES}"

# 4. One task per node: the mesh, by tiles when the input exceeds
#    DelaunayMeshing.max_memory_gb (each rank meshes its share of the tiles
#    and holds the whole input once; rank 0 merges and writes). The same
#    inputs and options as the pipeline's mesh stage: the refined model's 3D
#    lines when it has any.
LINES=()
if [[ -f "${WORKSPACE}/sparse/refined/lines3D.bin" ]]; then
  LINES=(--lines_path "${WORKSPACE}/sparse/refined"
         --database_path "${WORKSPACE}/database.db")
fi
srun --ntasks-per-node=1 --cpus-per-task="${NODE_CORES}" \
  "${BIN}" lidar_delaunay_mesher --workspace_path "${WORKSPACE}/dense" \
  --output_path "${WORKSPACE}/dense/meshed-delaunay.ply" "${LINES[@]}" \
  --DelaunayMeshing.num_threads "${NODE_CORES}"

# 5. One process: evaluation (when the dataset has ground truth) and report.
srun --nodes=1 --ntasks=1 --cpus-per-task="${NODE_CORES}" \
  "${BIN}" automatic_reconstructor --workspace_path "${WORKSPACE}" \
  --dataset_path "${DATASET}" --AutomaticReconstruction.stages evaluate: \
  --AutomaticReconstruction.num_threads "${NODE_CORES}"
