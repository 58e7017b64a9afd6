#!/usr/bin/env bash
# Benchmark of lidar_mapper (issue 6) on the default synthetic scene: the
# whole camera + LIDAR pipeline from an imported workspace (stock SIFT
# features and matching, line extraction, association, point + line + LIDAR
# bundle adjustment), evaluated against the ground truth WITHOUT any
# alignment, next to stock COLMAP's mapper of the same run (sim3) and the
# lower bound of scripts/pose_gauge_bound.py (priors fix the world frame to
# about sigma / sqrt(N)).
#
# Usage: bash scripts/bench_lidar_mapper.sh [--dataset DIR] [--work DIR]
#          [--init mapper|priors] [--exhaustive_max N] [--overlap N]
#          [--reuse_matches DB] [--no-write] [-- extra lidar_mapper options]
# Default dataset: bench_work/quad_v2 (relative to the checkout), the default
# synthetic scene; if it is missing the script prints the synthesize command
# that makes it and exits 1. --reuse_matches copies a database that already
# holds the features and matches of the same dataset (skips SIFT and matching; the
# times then cover the rest only). Writes docs/benchmarks/lidar_mapper.md
# unless --no-write. Times: wall and CPU (user + system, all processes) of
# the lidar_mapper command, from /usr/bin/time; CPU time is the figure to
# compare on a shared machine.
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${COLMAP_LIDAR_BIN:-build/colmap-lidar}"
dataset=""
work=bench_work/lidar_mapper
init=mapper
write=1
reuse=""
extra=()
mapper_args=()
while [ $# -gt 0 ]; do
  case "$1" in
    --dataset) dataset="$2"; shift 2 ;;
    --work) work="$2"; shift 2 ;;
    --init) init="$2"; shift 2 ;;
    --exhaustive_max) mapper_args+=(--LidarMapper.exhaustive_max_num_images "$2"); shift 2 ;;
    --overlap) mapper_args+=(--LidarMapper.sequential_overlap "$2"); shift 2 ;;
    --reuse_matches) reuse="$2"; shift 2 ;;
    --no-write) write=0; shift ;;
    --) shift; extra=("$@"); break ;;
    *) echo "unknown argument $1" >&2; exit 2 ;;
  esac
done
[ -x "$bin" ] || { echo "build first: bash scripts/build.sh" >&2; exit 1; }
default_dataset=bench_work/quad_v2
synthesize_args="synthesize --output_path $default_dataset --Synthesis.preset quad --Synthesis.num_frames 60 --Synthesis.seed 0"
if [ -z "$dataset" ]; then
  dataset=$default_dataset
  [ -f "$dataset/calibration.yaml" ] || {
    echo "no default dataset at $dataset (calibration.yaml missing); make it with" >&2
    echo "  $bin $synthesize_args" >&2
    echo "or pass --dataset DIR" >&2
    exit 1
  }
fi
[ -f "$dataset/calibration.yaml" ] || { echo "no calibration.yaml in $dataset" >&2; exit 1; }
mkdir -p "$work"
# The dataset as the docs page names it: the synthesize command for the
# default scene, else its path relative to the checkout (no machine path).
if [ "$(realpath "$dataset")" = "$(realpath -m "$default_dataset")" ]; then
  dataset_label="\`$default_dataset\`, made by \`colmap-lidar $synthesize_args\` (preset quad, 60 frames, seed 0)"
elif [ "$(realpath --relative-base=. "$dataset")" != "$(realpath "$dataset")" ]; then
  dataset_label="\`$(realpath --relative-base=. "$dataset")\`"
else
  dataset_label="\`$(basename "$(realpath "$dataset")")\` (a folder outside the checkout)"
fi
ws="$work/workspace"
rm -rf "$ws"
if [ -n "$reuse" ]; then
  "$bin" lidar_importer --dataset_path "$dataset" --workspace_path "$ws" > "$work/import.log" 2>&1
  cp "$reuse" "$ws/database.db"
fi

/usr/bin/time -f "%e %U %S" -o "$work/time.txt" \
  "$bin" lidar_mapper --dataset_path "$dataset" --workspace_path "$ws" \
  --LidarMapper.init_method "$init" --LidarMapper.num_threads 2 \
  ${mapper_args[@]+"${mapper_args[@]}"} ${extra[@]+"${extra[@]}"} > "$work/lidar_mapper.log" 2>&1
read -r wall user sys < "$work/time.txt"
cpu=$(/usr/bin/python3 -c "print(f'{$user + $sys:.0f}')")
wall=$(/usr/bin/python3 -c "print(f'{$wall:.0f}')")
grep -E "^lidar_mapper:|^  (initial model|iteration|output|time|cpu time)" "$work/lidar_mapper.log" || true

evaluate() {  # model alignment json
  "$bin" pose_evaluator --input_path "$1" --ground_truth_path "$dataset/poses_gt.txt" \
    --output_path "$3" --PoseEvaluation.alignment "$2" > "${3%.json}.log" 2>&1 || true
}
evaluate "$ws/sparse/prior" none "$work/prior_none.json"
evaluate "$ws/sparse/refined" none "$work/refined_none.json"
evaluate "$ws/sparse/refined" sim3 "$work/refined_sim3.json"
# Stock mapper's model of the same run (the initialisation), largest model.
stock=""
if [ -d "$ws/sparse/lidar_mapper/mapper" ]; then
  stock=$(for d in "$ws"/sparse/lidar_mapper/mapper/*/; do
            [ -f "$d/images.bin" ] && echo "$(stat -c %s "$d/images.bin") $d"; done |
          sort -nr | head -1 | cut -d' ' -f2)
fi
[ -n "$stock" ] && evaluate "$stock" sim3 "$work/stock_sim3.json"

solve=$(grep -oE "iterations [0-9.]+ s \(adjustment [0-9.]+ s\)" "$work/lidar_mapper.log" | tail -1)
cpu_stages=$(grep -E "^  cpu time" "$work/lidar_mapper.log" | sed 's/^  //' | tail -1)
table=$(/usr/bin/python3 scripts/pose_table.py \
  "Prior poses (input, no alignment)|$work/prior_none.json|-" \
  "COLMAP mapper of this run (sim3)|$work/stock_sim3.json|-" \
  "lidar_mapper, init $init (no alignment)|$work/refined_none.json|$wall / $cpu" \
  "lidar_mapper, init $init (sim3, for reference)|$work/refined_sim3.json|$wall / $cpu")
echo "$table"
echo "Stage times: $solve; $cpu_stages"
bound=$(/usr/bin/python3 scripts/pose_gauge_bound.py --gt "$dataset/poses_gt.txt" \
  --prior "$dataset/poses_prior.txt" --trials 500)
echo "$bound"
if [ "$write" = 1 ]; then
  mkdir -p docs/benchmarks
  {
    echo "# lidar_mapper on the default synthetic scene"
    echo
    echo "Produced by \`bash scripts/bench_lidar_mapper.sh\` on $(date -u +%Y-%m-%d), $(nproc) cores."
    echo "Dataset: $dataset_label (priors with 0.5 m / 5 deg noise). Time: the whole command"
    echo "(import, SIFT, matching, lines, initialisation, iterations), wall / CPU seconds; $solve;"
    echo "$cpu_stages."
    echo
    echo "$table"
    echo
    echo "Lower bound without alignment (scripts/pose_gauge_bound.py):"
    echo
    echo "$bound"
  } > docs/benchmarks/lidar_mapper.md
fi
