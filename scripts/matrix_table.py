#!/usr/bin/env python3
"""The benchmark matrix's table (issue 14) from the work folder of
scripts/bench_matrix.sh: one row per cell, one column per figure, each
figure over the cell's runs as "worst (best)" when there are several; then
the worst cell of every column.

Usage: matrix_table.py --work DIR --cells_file FILE [--output FILE.md]

Reads, per run (<work>/<cell>/run<r>/):
  ws/pipeline/stages.json          wall / CPU seconds, peak memory per stage;
                                   the patch_match note: what confirmed the depth
  ws/eval/poses_*.json             pose errors (pose_evaluator schema)
  ws/eval/mesh_*.json              mesh P/R/F (mesh_evaluator schema)
  ws/eval/depth_maps.json          depth maps within 5 cm, coverage
  ws/eval/real_data.json           figures without ground truth (KITTI)
  matrix/lines_eval.json           segments vs crease edges (line_evaluator)
  matrix/tracks_{prior,refined}_eval.txt  scripts/eval_line_tracks.py output
  matrix/nolines_eval/mesh_ours*.json   ours without line samples
  matrix/gauge.txt                 scripts/pose_gauge_bound.py --prior output
Missing files give "-" (a stage that did not run or failed).
"""
import argparse
import glob
import json
import math
import os
import re
import sys

THRESHOLDS = (0.02, 0.05, 0.1, 0.5)


def load_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def read_text(path):
    try:
        with open(path) as f:
            return f.read()
    except OSError:
        return ""


def at_threshold(evaluation, key, threshold):
    if not evaluation or key not in evaluation:
        return None
    for t, v in zip(evaluation["thresholds_m"], evaluation[key]):
        if abs(t - threshold) < 1e-9:
            return v
    return None


class Column:
    """One figure: how to read it from a run and which way is better."""

    def __init__(self, key, title, getter, higher_is_better, fmt):
        self.key = key
        self.title = title
        self.getter = getter
        self.higher_is_better = higher_is_better
        self.fmt = fmt

    def worst(self, values):
        return min(values) if self.higher_is_better else max(values)

    def best(self, values):
        return max(values) if self.higher_is_better else min(values)


def pose(run, name, alignment, field):
    evaluation = load_json(f"{run}/ws/eval/poses_{name}_{alignment}.json")
    if not evaluation:
        return None
    return evaluation[field]["mean"]


def pose_axes(run, name, field):
    """After the sim3 fit of the centres AND orientations (Tanks and Temples;
    the centres alone leave the roll about a straight walk free); runs older
    than that fit fall back to the centres-only sim3."""
    value = pose(run, name, "sim3_axes", field)
    return value if value is not None else pose(run, name, "sim3", field)


def registered(run):
    evaluation = load_json(f"{run}/ws/eval/poses_refined_none.json")
    if not evaluation or not evaluation["num_ground_truth_frames"]:
        return None
    return evaluation["num_matched"] / evaluation["num_ground_truth_frames"]


def gauge_floor(run):
    text = read_text(f"{run}/matrix/gauge.txt")
    m = re.search(r"Oracle on .*\(6-DoF, rotation prior weight [0-9.]+ deg "
                  r"per-axis\): mean ([0-9.]+) m", text)
    return float(m.group(1)) if m else None


def pose_over_floor(run):
    none = pose(run, "refined", "none", "position_error_m")
    floor = gauge_floor(run)
    if none is None or not floor:
        return None
    return none / floor


def num_frames(run):
    evaluation = load_json(f"{run}/ws/eval/poses_refined_none.json")
    if evaluation:
        return evaluation["num_ground_truth_frames"]
    images = os.path.join(run, "ws", "images")
    return len(os.listdir(images)) if os.path.isdir(images) else None


def segments_per_frame(run):
    text = read_text(f"{run}/matrix/lines.log")
    # line_exporter: "Exported N segments ..." of the refined model.
    evaluation = load_json(f"{run}/matrix/lines_eval.json")
    frames = num_frames(run)
    if evaluation and frames:
        return evaluation["num_estimated_segments"] / frames
    m = re.search(r"(\d+) segments", text)
    if m and frames:
        return int(m.group(1)) / frames
    return None


def segment_precision(run):
    evaluation = load_json(f"{run}/matrix/lines_eval.json")
    if not evaluation:
        return None
    i = evaluation["thresholds_m"].index(0.05)
    return evaluation["inlier_segment_share"][i]


def segment_recall(run):
    evaluation = load_json(f"{run}/matrix/lines_eval.json")
    if not evaluation:
        return None
    i = evaluation["thresholds_m"].index(0.05)
    return evaluation["length_recall"][i]


def tracks(run, what, poses="refined"):
    text = read_text(f"{run}/matrix/tracks_{poses}_eval.txt")
    patterns = {
        "count": r"tracks (\d+)",
        "length": r"mean track length ([0-9.]+)",
        "purity": r"precision ([0-9.]+)%",
        "not_vertical": r"not vertical ([0-9.]+)%",
    }
    m = re.search(patterns[what], text)
    if not m:
        return None
    value = float(m.group(1))
    return value / 100.0 if what in ("purity", "not_vertical") else value


def depth(run, key):
    evaluation = load_json(f"{run}/ws/eval/depth_maps.json")
    if not evaluation:
        return None
    overall = evaluation.get("overall", evaluation)
    for source in ("geometric", "photometric"):
        if isinstance(overall.get(source), dict):
            overall = overall[source]
            break
    value = overall.get(key)
    return value


def patch_match_note(run):
    """The patch_match stage record's note ("" when there is none)."""
    records = load_json(f"{run}/ws/pipeline/stages.json")
    for record in (records or {}).get("stages", []):
        if record["stage"] == "patch_match":
            return record.get("note", "")
    return ""


def depth_support(run, what):
    """Share (0-1) of the geometric pixels by what confirmed them, from the
    patch_match stage record's note (colmap-lidar's DepthSupportCounts:
    "... N pixels: a % images only, b % images and LIDAR, c % need the LIDAR
    (d % the LIDAR alone)")."""
    match = re.search(r"pixels: ([\d.]+) % images only, ([\d.]+) % images and "
                      r"LIDAR, ([\d.]+) % need the LIDAR \(([\d.]+) % the LIDAR alone\)",
                      patch_match_note(run))
    if not match:
        return None
    index = {"images_only": 1, "both": 2, "need_lidar": 3, "lidar_only": 4}[what]
    return float(match.group(index)) / 100.0


def depth_not_fused(run):
    """Share (0-1) of the geometric pixels kept out of fusion (the LIDAR's
    vote or the parallax tolerance alone kept them), from the patch_match
    stage record's note ("geometric N pixels: ...; M kept out of fusion")."""
    match = re.search(r"geometric (\d+) pixels:.*; (\d+) kept out of fusion",
                      patch_match_note(run))
    if not match or int(match.group(1)) == 0:
        return None
    return int(match.group(2)) / int(match.group(1))


def mesh(run, name, threshold, field="fscore"):
    return at_threshold(load_json(f"{run}/ws/eval/mesh_{name}.json"), field,
                        threshold)


def mesh_nolines(run, threshold):
    return at_threshold(
        load_json(f"{run}/matrix/nolines_eval/mesh_ours.json"), "fscore",
        threshold)


def edge_region(path, threshold, field):
    evaluation = load_json(path)
    if not evaluation or "edge_region" not in evaluation:
        return None
    region = dict(evaluation["edge_region"])
    region["thresholds_m"] = evaluation["thresholds_m"]
    return at_threshold(region, field, threshold)


def mesh_edge(run, name, threshold, field):
    """Figures within 0.2 m of the true creases (src/eval/edge_region.h)."""
    path = (f"{run}/matrix/nolines_eval/mesh_ours.json" if name == "nolines"
            else f"{run}/ws/eval/mesh_{name}.json")
    return edge_region(path, threshold, field)


def edge_line_gain(run, threshold):
    ours = mesh_edge(run, "ours", threshold, "precision")
    nolines = mesh_edge(run, "nolines", threshold, "precision")
    if ours is None or nolines is None:
        return None
    return ours - nolines


def mesh_gain(run, threshold):
    ours = mesh(run, "ours", threshold)
    lidar = mesh(run, "lidar_poisson", threshold)
    if ours is None or lidar is None:
        return None
    return ours - lidar


def stage_seconds(run, field, stages=None):
    records = load_json(f"{run}/ws/pipeline/stages.json")
    if not records:
        return None
    total = 0.0
    for record in records.get("stages", []):
        if stages is None or record["stage"] in stages:
            total += record[field]
    return total


def peak_memory_gib(run):
    records = load_json(f"{run}/ws/pipeline/stages.json")
    if not records:
        return None
    peaks = [r["peak_memory_bytes"] for r in records.get("stages", [])]
    return max(peaks) / 2**30 if peaks else None


def real(run, key):
    evaluation = load_json(f"{run}/ws/eval/real_data.json")
    if not evaluation:
        return None
    # Keys may hold dots themselves ("lidar_within_0.1m"): at each level take
    # the shortest run of dotted parts that names a key.
    node = evaluation
    parts = key.split(".")
    while parts:
        for n in range(1, len(parts) + 1):
            name = ".".join(parts[:n])
            if isinstance(node, dict) and name in node:
                node = node[name]
                parts = parts[n:]
                break
        else:
            return None
    return node if isinstance(node, (int, float)) else None


def pct(v):
    return f"{100 * v:.1f}"


def f3(v):
    return f"{v:.3f}"


def cm(v):
    return f"{100 * v:.2f}"


COLUMNS = [
    Column("registered", "images registered %", registered, True, pct),
    Column("segments", "3D segments / frame", segments_per_frame, True,
           lambda v: f"{v:.1f}"),
    Column("seg_prec", "segments within 5 cm %", segment_precision, True, pct),
    Column("seg_recall", "crease length recall @5 cm %", segment_recall, True,
           pct),
    Column("tracks_prior", "tracks, noisy priors",
           lambda r: tracks(r, "count", "prior"), True, lambda v: f"{v:.0f}"),
    Column("track_pure_prior", "pure tracks, noisy priors %",
           lambda r: tracks(r, "purity", "prior"), True, pct),
    Column("tracks", "tracks, refined poses", lambda r: tracks(r, "count"),
           True, lambda v: f"{v:.0f}"),
    Column("track_len", "mean track length, refined poses",
           lambda r: tracks(r, "length"), True, lambda v: f"{v:.2f}"),
    Column("track_pure", "pure tracks, refined poses %",
           lambda r: tracks(r, "purity"), True, pct),
    Column("track_horizontal", "tracks not vertical, refined poses %",
           lambda r: tracks(r, "not_vertical"), True, pct),
    Column("pose_none", "position, no alignment, cm",
           lambda r: pose(r, "refined", "none", "position_error_m"), False,
           cm),
    Column("pose_floor", "... / floor of the priors", pose_over_floor, False,
           lambda v: f"{v:.2f}"),
    Column("pose_sim3", "position after sim3 (centres + axes), cm",
           lambda r: pose_axes(r, "refined", "position_error_m"), False,
           cm),
    Column("rot_sim3", "rotation after sim3 (centres + axes), deg",
           lambda r: pose_axes(r, "refined", "rotation_error_deg"), False,
           lambda v: f"{v:.3f}"),
    Column("mapper_sim3", "stock mapper after sim3, cm",
           lambda r: pose(r, "colmap_mapper", "sim3", "position_error_m"),
           False, cm),
    Column("depth_5cm", "depth within 5 cm %",
           lambda r: depth(r, "within_5cm"), True, pct),
    Column("depth_surface_5cm", "depth within 5 cm of the true surface %",
           lambda r: depth(r, "surface_within_5cm"), True, pct),
    Column("depth_cov", "depth coverage %", lambda r: depth(r, "coverage"),
           True, pct),
    Column("depth_images_only", "depth pixels from the images only %",
           lambda r: depth_support(r, "images_only"), True, pct),
    Column("depth_both", "depth pixels from the images and the LIDAR %",
           lambda r: depth_support(r, "both"), True, pct),
    Column("depth_need_lidar", "depth pixels that need the LIDAR %",
           lambda r: depth_support(r, "need_lidar"), False, pct),
    Column("depth_lidar_only", "depth pixels from the LIDAR alone %",
           lambda r: depth_support(r, "lidar_only"), False, pct),
    Column("depth_not_fused", "depth pixels kept out of fusion %",
           depth_not_fused, False, pct),
]
for t in THRESHOLDS:
    label = f"{t:g}"
    COLUMNS.append(Column(f"f_ours_{label}", f"F ours @{label} m",
                          lambda r, t=t: mesh(r, "ours", t), True, f3))
    COLUMNS.append(Column(f"f_lidar_{label}", f"F LIDAR-only @{label} m",
                          lambda r, t=t: mesh(r, "lidar_poisson", t), True,
                          f3))
    COLUMNS.append(Column(f"f_nolines_{label}", f"F ours, no lines @{label} m",
                          lambda r, t=t: mesh_nolines(r, t), True, f3))
# After the ICP refinement of the mesh alignment (mesh_*_icp.json, evaluate
# stage with AutomaticReconstruction.mesh_icp; empty for older runs).
for t in (0.05, 0.1, 0.5):
    label = f"{t:g}"
    COLUMNS.append(Column(f"f_ours_icp_{label}", f"F ours after ICP @{label} m",
                          lambda r, t=t: mesh(r, "ours_icp", t), True, f3))
    COLUMNS.append(Column(f"f_lidar_icp_{label}",
                          f"F LIDAR-only after ICP @{label} m",
                          lambda r, t=t: mesh(r, "lidar_poisson_icp", t),
                          True, f3))
for t in (0.05, 0.1):
    COLUMNS.append(Column(f"gain_{t:g}", f"F ours - LIDAR-only @{t:g} m",
                          lambda r, t=t: mesh_gain(r, t), True,
                          lambda v: f"{v:+.3f}"))
COLUMNS.append(Column("p_ours_0.5", "precision ours @0.5 m",
                      lambda r: mesh(r, "ours", 0.5, "precision"), True, f3))
# Near the creases (0.2 m of a ground-truth crease edge): where the line
# samples are meant to help (issue 17's edge-region target).
for name, title in (("ours", "ours"), ("nolines", "ours, no lines"),
                    ("lidar_poisson", "LIDAR-only")):
    COLUMNS.append(Column(f"edge_p_{name}_0.05",
                          f"edge region: precision {title} @0.05 m",
                          lambda r, n=name: mesh_edge(r, n, 0.05, "precision"),
                          True, f3))
    COLUMNS.append(Column(f"edge_f_{name}_0.1",
                          f"edge region: F {title} @0.1 m",
                          lambda r, n=name: mesh_edge(r, n, 0.1, "fscore"),
                          True, f3))
# The line samples and the crease snapping move the mesh by millimetres
# near the few creases that lines were found on: four decimals, and 0.02 m
# too, where they show.
for t in (0.02, 0.05):
    COLUMNS.append(Column(f"edge_p_line_gain_{t:g}",
                          f"edge region: precision with lines - without @{t:g} m",
                          lambda r, t=t: edge_line_gain(r, t), True,
                          lambda v: f"{v:+.4f}"))
for name, stages in (("sfm", ("sfm",)),
                     ("dense", ("dense", "patch_match", "fusion")),
                     ("mesh", ("mesh",)), ("total", None)):
    COLUMNS.append(Column(f"wall_{name}", f"wall s, {name}",
                          lambda r, s=stages: stage_seconds(r, "wall_seconds",
                                                            s),
                          False, lambda v: f"{v:.0f}"))
COLUMNS.append(Column("cpu_total", "CPU s, all stages",
                      lambda r: stage_seconds(r, "cpu_seconds"), False,
                      lambda v: f"{v:.0f}"))
COLUMNS.append(Column("peak_gib", "peak memory GiB", peak_memory_gib, False,
                      lambda v: f"{v:.2f}"))

REAL_COLUMNS = [
    Column("length_ratio", "trajectory length / odometry's",
           lambda r: real(r, "trajectory.length_ratio"), None,
           lambda v: f"{v:.3f}"),
    Column("max_step", "largest step difference, cm",
           lambda r: real(r, "trajectory.max_step_difference_m"), False, cm),
    Column("crisp_refined", "map crispness, refined poses, cm",
           lambda r: real(r, "crispness.refined_median_m"), False, cm),
    Column("crisp_prior", "map crispness, prior poses, cm",
           lambda r: real(r, "crispness.prior_median_m"), False, cm),
    Column("lidar_near_mesh", "LIDAR within 0.1 m of the mesh %",
           lambda r: real(r, "mesh_vs_lidar.lidar_within_0.1m"), True, pct),
    Column("lidar_in_view_near_mesh",
           "LIDAR in the cameras' view (40 m) within 0.1 m of the mesh %",
           lambda r: real(r, "mesh_vs_lidar.lidar_in_view_within_0.1m"), True,
           pct),
    Column("mesh_near_lidar", "mesh within 0.1 m of the LIDAR %",
           lambda r: real(r, "mesh_vs_lidar.mesh_within_0.1m"), True, pct),
]


def read_cells(path):
    cells = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            name, _, options = line.partition(" ")
            cells.append((name, options.strip()))
    return cells


def cell_values(work, cell, columns):
    runs = sorted(glob.glob(os.path.join(work, cell, "run*")))
    runs = [r for r in runs if not os.path.exists(os.path.join(r, "failed"))]
    values = {}
    for column in columns:
        got = []
        for run in runs:
            try:
                v = column.getter(run)
            except (KeyError, ValueError, TypeError, ZeroDivisionError):
                v = None
            if v is not None and not (isinstance(v, float) and math.isnan(v)):
                got.append(v)
        values[column.key] = got
    return len(runs), values


def format_values(column, got):
    if not got:
        return "-"
    if column.higher_is_better is None:
        worst = max(got, key=lambda v: abs(v - 1.0))
        best = min(got, key=lambda v: abs(v - 1.0))
    else:
        worst, best = column.worst(got), column.best(got)
    if len(got) == 1:
        return column.fmt(worst)
    return f"{column.fmt(worst)} ({column.fmt(best)})"


def table(cells, work, columns, title):
    rows = []
    per_cell = {}
    for name, _ in cells:
        if not os.path.isdir(os.path.join(work, name)):
            continue
        num_runs, values = cell_values(work, name, columns)
        if num_runs == 0:
            continue
        per_cell[name] = values
        rows.append((name, num_runs, values))
    if not rows:
        return []
    out = [f"### {title}", ""]
    # Transposed: one row per figure, one column per cell, then the worst.
    out.append("| figure | " + " | ".join(f"{n} ({k})" for n, k, _ in rows) +
               " | worst cell |")
    out.append("|---|" + "---|" * (len(rows) + 1))
    for column in columns:
        cells_text = [format_values(column, v[column.key]) for _, _, v in rows]
        worst_cell = "-"
        candidates = [(n, column.worst(v[column.key]) if column.higher_is_better
                       is not None else max(v[column.key],
                                            key=lambda x: abs(x - 1.0)))
                      for n, _, v in rows if v[column.key]]
        if candidates:
            if column.higher_is_better is None:
                n, v = max(candidates, key=lambda c: abs(c[1] - 1.0))
            elif column.higher_is_better:
                n, v = min(candidates, key=lambda c: c[1])
            else:
                n, v = max(candidates, key=lambda c: c[1])
            worst_cell = f"{column.fmt(v)} ({n})"
        out.append(f"| {column.title} | " + " | ".join(cells_text) +
                   f" | {worst_cell} |")
    out.append("")
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--work", required=True)
    parser.add_argument("--cells_file", required=True)
    parser.add_argument("--output")
    args = parser.parse_args()
    cells = read_cells(args.cells_file)
    synthetic = [c for c in cells if c[0] != "kitti"]
    real_cells = [c for c in cells if c[0] == "kitti"]
    lines = ["# Benchmark matrix", "",
             "Produced by `bash scripts/bench_matrix.sh` (cells in "
             "`scripts/matrix_cells.txt`, each synthesized with "
             "`colmap-lidar synthesize` and those options; default options "
             "everywhere else). A cell with several runs of the same commit "
             "shows `worst (best)`; the last column is the worst cell. "
             "Columns `(n)` give the number of runs.", ""]
    lines += ["## Cells", "", "| cell | synthesize options |", "|---|---|"]
    for name, options in cells:
        lines.append(f"| {name} | `{options or '(real data: --kitti)'}` |")
    lines.append("")
    lines += table(synthetic, args.work, COLUMNS, "Synthetic cells")
    lines += table(real_cells, args.work,
                   [c for c in COLUMNS if c.key in (
                       "registered", "segments", "tracks", "track_len",
                       "wall_sfm", "wall_dense", "wall_mesh", "wall_total",
                       "cpu_total", "peak_gib")] + REAL_COLUMNS,
                   "Real data (no ground truth)")
    text = "\n".join(lines) + "\n"
    sys.stdout.write(text)
    if args.output:
        tmp = args.output + ".tmp"
        with open(tmp, "w") as f:
            f.write(text)
        os.replace(tmp, args.output)


if __name__ == "__main__":
    main()
