#!/usr/bin/env bash
# Baseline benchmark (issue 3): stock COLMAP on a synthetic recording, as a
# user would run it, evaluated against the ground-truth poses.
#   1. SfM: CPU SIFT, matcher, `mapper` (no priors; evaluated after a sim3
#      alignment, as the paper does for SfM without metric scale);
#   2. known-pose route: `point_triangulator` on the prior model, then
#      `bundle_adjuster` (evaluated without alignment and after sim3).
# Prints a markdown table (localisation error, wall time) and writes it to
# docs/benchmarks/baseline_colmap.md unless --no-write is given.
#
# Usage: bash scripts/bench_baseline_colmap.sh [--dataset DIR] [--work DIR] [--no-write]
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${COLMAP_LIDAR_BIN:-build/colmap-lidar}"
dataset=""
work=bench_work/baseline_colmap
write=1
while [ $# -gt 0 ]; do
  case "$1" in
    --dataset) dataset="$2"; shift 2 ;;
    --work) work="$2"; shift 2 ;;
    --no-write) write=0; shift ;;
    *) echo "unknown argument $1" >&2; exit 2 ;;
  esac
done
[ -x "$bin" ] || { echo "build first: bash scripts/build.sh" >&2; exit 1; }
mkdir -p "$work"
if [ -z "$dataset" ]; then
  dataset="$work/dataset"
  if [ ! -f "$dataset/calibration.yaml" ]; then
    "$bin" synthesize --output_path "$dataset"
  fi
fi
ws="$work/workspace"
rm -rf "$ws"
"$bin" lidar_importer --dataset_path "$dataset" --workspace_path "$ws" > "$work/import.log" 2>&1
db="$ws/database.db"
num_images=$(ls "$ws/images" | wc -l)

now() { date +%s.%N; }
elapsed() { python3 -c "print(f'{$2 - $1:.1f}')"; }

t0=$(now)
colmap feature_extractor --database_path "$db" --image_path "$ws/images" \
  --SiftExtraction.use_gpu 0 --SiftExtraction.num_threads 2 > "$work/features.log" 2>&1
# Exhaustive matching up to 100 images, sequential with loop detection off beyond.
if [ "$num_images" -le 100 ]; then
  colmap exhaustive_matcher --database_path "$db" --SiftMatching.use_gpu 0 > "$work/matching.log" 2>&1
else
  colmap sequential_matcher --database_path "$db" --SiftMatching.use_gpu 0 \
    --SequentialMatching.overlap 15 > "$work/matching.log" 2>&1
fi
t1=$(now)
mkdir -p "$ws/sparse/mapper"
colmap mapper --database_path "$db" --image_path "$ws/images" --output_path "$ws/sparse/mapper" \
  --Mapper.ba_refine_focal_length 0 --Mapper.ba_refine_principal_point 0 \
  --Mapper.ba_refine_extra_params 0 --Mapper.num_threads 2 > "$work/mapper.log" 2>&1
t2=$(now)
mkdir -p "$ws/sparse/triangulated" "$ws/sparse/known_pose"
colmap point_triangulator --database_path "$db" --image_path "$ws/images" \
  --input_path "$ws/sparse/prior" --output_path "$ws/sparse/triangulated" > "$work/triangulator.log" 2>&1
colmap bundle_adjuster --input_path "$ws/sparse/triangulated" --output_path "$ws/sparse/known_pose" \
  --BundleAdjustment.refine_focal_length 0 --BundleAdjustment.refine_principal_point 0 \
  --BundleAdjustment.refine_extra_params 0 > "$work/bundle_adjuster.log" 2>&1
t3=$(now)

# The largest model of the mapper is the one with most images.
best=""; best_n=0
for m in "$ws"/sparse/mapper/*/; do
  n=$(python3 -c "import struct,sys; f=open('$m/images.bin','rb'); print(struct.unpack('<Q', f.read(8))[0])")
  if [ "$n" -gt "$best_n" ]; then best="$m"; best_n=$n; fi
done

evaluate() {  # model alignment json
  "$bin" pose_evaluator --input_path "$1" --ground_truth_path "$dataset/poses_gt.txt" \
    --output_path "$3" --PoseEvaluation.alignment "$2" > "${3%.json}.log" 2>&1
}
evaluate "$ws/sparse/prior" none "$work/prior_none.json"
[ -n "$best" ] && evaluate "$best" sim3 "$work/mapper_sim3.json"
evaluate "$ws/sparse/known_pose" none "$work/known_pose_none.json"
evaluate "$ws/sparse/known_pose" sim3 "$work/known_pose_sim3.json"

t_feat=$(elapsed "$t0" "$t1"); t_map=$(elapsed "$t1" "$t2"); t_known=$(elapsed "$t2" "$t3")
table=$(python3 scripts/pose_table.py \
  "Prior poses (input, no alignment)|$work/prior_none.json|-" \
  "COLMAP mapper (sim3), $best_n/$num_images images|$work/mapper_sim3.json|$t_feat + $t_map" \
  "COLMAP known poses: point_triangulator + bundle_adjuster (no alignment)|$work/known_pose_none.json|$t_feat + $t_known" \
  "COLMAP known poses: point_triangulator + bundle_adjuster (sim3)|$work/known_pose_sim3.json|$t_feat + $t_known")
echo "$table"
if [ "$write" = 1 ]; then
  mkdir -p docs/benchmarks
  {
    echo "# Baseline: stock COLMAP 3.8 on the default synthetic scene"
    echo
    echo "Produced by \`bash scripts/bench_baseline_colmap.sh\` on $(date -u +%Y-%m-%d), $(nproc) cores."
    echo "Dataset: \`colmap-lidar synthesize\` defaults ($num_images frames, priors with 0.5 m / 5 deg noise)."
    echo "Times: feature extraction + matching, then the reconstruction step, in seconds."
    echo
    echo "$table"
  } > docs/benchmarks/baseline_colmap.md
fi
