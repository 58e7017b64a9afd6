#!/usr/bin/env python3
"""Markdown tables of scripts/baselines/bench_baselines.sh: per cell, the
OpenMVG variants, stock COLMAP's mapper and colmap-lidar's runs (poses), and
OpenMVG + OpenMVS, colmap-lidar and LIDAR-only Poisson (meshes), each figure
the median and the worst over the runs, "median (worst)".

Poses: images registered; camera position / rotation error after the sim3 of
centres and axes to the ground truth and the relative pose error per step
between consecutive frames (pose_evaluator); and the paper's Table I
protocol, computed here from the models: the baselines sim3-aligned to the
noisy prior centres (Umeyama), colmap-lidar unaligned, then the mean position
error against the ground truth; a mean over fewer frames is not the same
figure, so where a baseline registered fewer frames than colmap-lidar, the
summary also gives colmap-lidar's over that baseline's frames (every run of
ours on every run's frames of the baseline), and judges on those.
Meshes: F-score at 0.05, 0.1 and 0.5 m and precision at 0.5 m, after the
alignment by the model's cameras and after ICP (mesh_evaluator), with recall
on the LIDAR-covered reference and on the whole reference the true cameras
see (the paper's protocol).

Usage: baselines_table.py --work DIR --cells a,b [--summary]
  --summary  two tables with one row per cell: poses (per figure the best
             OpenMVG variant among those registering at least half the
             frames, stock COLMAP's mapper, colmap-lidar; bold where
             colmap-lidar's worst run beats both baselines' medians) and the
             meshes' F after ICP on both regions of recall
"""
import argparse
import functools
import glob
import json
import os
import struct
import sys

import numpy as np


def quaternion_matrix(w, x, y, z):
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


@functools.lru_cache(maxsize=None)
def read_centres(model):
    """Camera centres by image name stem of a COLMAP model (text or binary).
    Read once per model (Table I reads a model once per rival run); the
    returned dict is shared: callers must not modify it."""
    centres = {}
    text, binary = os.path.join(model, "images.txt"), os.path.join(model, "images.bin")
    if os.path.exists(binary):
        with open(binary, "rb") as f:
            (count,) = struct.unpack("<Q", f.read(8))
            for _ in range(count):
                f.read(4)
                q = struct.unpack("<4d", f.read(32))
                t = np.array(struct.unpack("<3d", f.read(24)))
                f.read(4)
                name = b""
                while (c := f.read(1)) != b"\0":
                    name += c
                (num_points,) = struct.unpack("<Q", f.read(8))
                f.read(24 * num_points)
                rotation = quaternion_matrix(*q)
                centres[os.path.splitext(name.decode())[0]] = -rotation.T @ t
    elif os.path.exists(text):
        lines = [l for l in open(text).read().splitlines() if l and not l.startswith("#")]
        for line in lines[0::2]:
            p = line.split()
            rotation = quaternion_matrix(*map(float, p[1:5]))
            t = np.array(list(map(float, p[5:8])))
            centres[os.path.splitext(p[9])[0]] = -rotation.T @ t
    return centres


@functools.lru_cache(maxsize=None)
def read_pose_file(path):
    """Centres (world_from_cam translations) by frame of a poses_*.txt; read
    once per file, the returned dict shared (not to be modified)."""
    centres = {}
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        p = line.split()
        centres[p[0]] = np.array(list(map(float, p[1:4])))
    return centres


def umeyama(source, target):
    """s, R, t minimising |s R source + t - target|^2 (rows are points)."""
    mu_s, mu_t = source.mean(0), target.mean(0)
    covariance = (target - mu_t).T @ (source - mu_s) / len(source)
    u, d, vt = np.linalg.svd(covariance)
    sign = np.eye(3)
    sign[2, 2] = np.sign(np.linalg.det(u) * np.linalg.det(vt))
    rotation = u @ sign @ vt
    scale = np.trace(np.diag(d) @ sign) / ((source - mu_s) ** 2).sum(1).mean()
    return scale, rotation, mu_t - scale * rotation @ mu_s


def paper_position_error(model, dataset, align_to_priors, frames=None):
    """Mean position error (m) against the ground truth, the model aligned
    to the prior centres by Umeyama's sim3 or not at all; over the images
    named in `frames` only when given (the frames another method
    registered)."""
    centres = read_centres(model)
    truth = read_pose_file(os.path.join(dataset, "poses_gt.txt"))
    names = sorted(set(centres) & set(truth))
    if frames is not None:
        names = [n for n in names if n in frames]
    if len(names) < 3:
        return None
    estimate = np.array([centres[n] for n in names])
    if align_to_priors:
        priors = read_pose_file(os.path.join(dataset, "poses_prior.txt"))
        names_p = [n for n in names if n in priors]
        s, r, t = umeyama(np.array([centres[n] for n in names_p]),
                          np.array([priors[n] for n in names_p]))
        estimate = (s * (r @ estimate.T)).T + t
    return float(np.linalg.norm(estimate - np.array([truth[n] for n in names]), axis=1).mean())


def load(path):
    try:
        return json.load(open(path))
    except (OSError, ValueError):
        return None


def median_worst(values, worst=max, digits=2):
    values = [v for v in values if v is not None]
    if not values:
        return "-"
    return f"{np.median(values):.{digits}f} ({worst(values):.{digits}f})"


BASELINES = [(f"OpenMVG {v.replace('_', ' + ')}", f"run*/openmvg_{v}")
             for v in ("global", "global_priors", "incremental", "incremental_priors")]
BASELINES.append(("stock COLMAP mapper", "run*/colmap_mapper"))


def pose_figures(cell_dir, dataset, pattern, baseline):
    """Per run of one method: images registered, the paper's Table I error
    (m), position (cm) and rotation (deg) after the sim3 to the truth, and
    the relative pose error per step (mm, deg); None where a run failed.
    Also, per run that has a model, its path and the names of the images it
    registered ("model", "frames")."""
    runs = sorted(glob.glob(os.path.join(cell_dir, "baselines", pattern)))
    figures = {k: [] for k in ("registered", "paper", "position", "rotation",
                               "step_mm", "step_deg", "model", "frames")}
    for run in runs:
        result = load(os.path.join(run, "poses.json"))
        if result is None:
            figures["registered"].append(0)
            continue
        figures["registered"].append(result["num_matched"])
        figures["position"].append(100 * result["position_error_m"]["mean"])
        figures["rotation"].append(result["rotation_error_deg"]["mean"])
        steps = result.get("step_translation_error_m")
        figures["step_mm"].append(1000 * steps["mean"] if steps else None)
        steps = result.get("step_rotation_error_deg")
        figures["step_deg"].append(steps["mean"] if steps else None)
        model = (os.path.join(run, "colmap") if baseline else
                 os.path.join(cell_dir, os.path.basename(run).replace("ours_", ""),
                              "ws", "sparse", "refined"))
        figures["paper"].append(paper_position_error(model, dataset, baseline))
        figures["model"].append(model)
        figures["frames"].append(set(read_centres(model)))
    return len(runs), figures


def pose_rows(cell_dir, dataset):
    rows = [(label, pattern, True) for label, pattern in BASELINES]
    rows.append(("colmap-lidar (default)", "ours_run*", False))
    total = len(read_pose_file(os.path.join(dataset, "poses_gt.txt")))
    out = []
    for label, pattern, baseline in rows:
        runs, f = pose_figures(cell_dir, dataset, pattern, baseline)
        out.append(f"| {label} | {runs} | {median_worst(f['registered'], min, 0)} / {total} | "
                   f"{median_worst(f['paper'], max, 3)} | {median_worst(f['position'])} | "
                   f"{median_worst(f['rotation'], max, 3)} | {median_worst(f['step_mm'], max, 1)} | "
                   f"{median_worst(f['step_deg'], max, 3)} |")
    return out


MESHES = [("OpenMVG + OpenMVS (refined)", "run*/openmvs/scene_refined"),
          ("colmap-lidar (default)", "ours_run*/mesh"),
          ("LIDAR-only Poisson", "ours_run*/lidar_poisson")]
# The two regions of recall: the LIDAR-covered reference and the whole
# reference the true cameras see (the paper's), files *_eval / *_visible.
REGIONS = (("_eval", "LIDAR-covered reference"), ("_visible", "whole visible reference"))


def mesh_values(cell_dir, prefix, region, threshold, key="fscore", icp=True):
    values = []
    for path in sorted(glob.glob(os.path.join(cell_dir, "baselines", prefix + region + ".json"))):
        result = load(path.replace(".json", "_icp.json") if icp else path)
        if result is not None:
            values.append(dict(zip(result["thresholds_m"], result[key])).get(threshold))
    return values


def mesh_rows(cell_dir):
    out = []
    for label, prefix in MESHES:
        runs = len(glob.glob(os.path.join(cell_dir, "baselines", prefix + "_eval.json")))
        cells = []
        for region, _ in REGIONS:
            for icp in (False, True):
                cells += [median_worst(mesh_values(cell_dir, prefix, region, t, icp=icp), min, 3)
                          for t in (0.05, 0.1, 0.5)]
                cells.append(median_worst(mesh_values(cell_dir, prefix, region, 0.5, "precision",
                                                      icp), min, 3))
        if "OpenMVS" in label:
            # The OpenMVG variant each run's OpenMVS worked on.
            used = []
            for path in sorted(glob.glob(os.path.join(cell_dir, "baselines", "run*", "openmvs",
                                                      "openmvg_variant.txt"))):
                used.append(os.path.basename(open(path).read().strip())
                            .replace("openmvg_", "").replace("_", " + "))
            if used:
                label += " on OpenMVG " + ", ".join(used)
        out.append(f"| {label} | {runs} | " + " | ".join(cells) + " |")
    return out


def best_baseline(variants, key, total):
    """Of `variants` [(label, figures of pose_figures)], the one with the
    lowest median of `key` among those whose median run registered at least
    half the frames (fewer make the sim3 trivially good): (label, figures
    without the failed runs) or None."""
    best = None
    for label, f in variants:
        values = [v for v in f[key] if v is not None]
        if not values or np.median(f["registered"]) < total / 2:
            continue
        if best is None or np.median(values) < np.median(best[1][key]):
            best = (label, {k: [v for v in vs if v is not None] for k, vs in f.items()})
    return best


POSE_KEYS = [("paper", "Table I, m", max, 3), ("position", "position after sim3, cm", max, 2),
             ("rotation", "rotation after sim3, deg", max, 3),
             ("step_mm", "per step, mm", max, 1), ("step_deg", "per step, deg", max, 3)]


def ours_on_frames(ours, dataset, frames_per_run):
    """Table I's error of every run of ours (unaligned) over the frames of
    every run of a rival (each a set of image names)."""
    values = []
    for frames in frames_per_run:
        for model in ours["model"]:
            value = paper_position_error(model, dataset, False, frames)
            if value is not None:
                values.append(value)
    return values


def summary_pose_rows(work, cells):
    """Per cell and figure: the best OpenMVG variant, stock COLMAP's mapper
    and colmap-lidar, each "median (worst)"; a figure where colmap-lidar's
    worst run beats both baselines' medians is in bold."""
    out = []
    for cell in cells:
        cell_dir = os.path.join(work, cell)
        dataset = os.path.join(cell_dir, "dataset")
        if not os.path.exists(os.path.join(dataset, "poses_gt.txt")):
            continue
        total = len(read_pose_file(os.path.join(dataset, "poses_gt.txt")))
        _, ours = pose_figures(cell_dir, dataset, "ours_run*", False)
        # Every baseline's runs read once (models and evaluations).
        baselines = [(label, pose_figures(cell_dir, dataset, pattern, True)[1])
                     for label, pattern in BASELINES]
        mapper = baselines[-1][1]
        row = [cell, f"{median_worst(ours['registered'], min, 0)} / {total}",
               ", ".join(median_worst(f["registered"], min, 0) for _, f in baselines)]
        for key, _, worst, digits in POSE_KEYS:
            best = best_baseline(baselines[:-1], key, total)
            mapper_values = ([v for v in mapper[key] if v is not None]
                             if np.median(mapper["registered"] or [0]) >= total / 2 else [])
            ours_values = [v for v in ours[key] if v is not None]
            # (rival's median, ours compared with it): a mean over other
            # frames is another figure, so where a rival registered fewer
            # frames than ours, Table I's mean is also taken over its frames.
            rivals = []
            same_frames = []
            for name, figures in ((best[0] if best else "", best and best[1]),
                                  ("the stock mapper", mapper if mapper_values else None)):
                if not figures:
                    continue
                compared = ours_values
                if (key == "paper" and ours["registered"] and
                        min(figures["registered"] or [0]) < min(ours["registered"])):
                    compared = ours_on_frames(ours, dataset, figures["frames"])
                    same_frames.append(f"{median_worst(compared, worst, digits)} on the frames of {name}")
                rivals.append((np.median([v for v in figures[key] if v is not None]), compared))
            text = median_worst(ours_values, worst, digits)
            if same_frames:
                text += f" [{'; '.join(same_frames)}]"
            if ours_values and rivals and all(compared and max(compared) < median
                                              for median, compared in rivals):
                text = f"**{text}**"
            mvg = (f"{median_worst(best[1][key], worst, digits)} ({best[0].replace('OpenMVG ', '')})"
                   if best else "-")
            row.append(f"{mvg}; {median_worst(mapper_values, worst, digits)}; {text}")
        out.append("| " + " | ".join(row) + " |")
    return out


def summary_mesh_rows(work, cells):
    """Per cell: F at 0.05 / 0.1 / 0.5 m after ICP, on both regions of
    recall, for OpenMVG + OpenMVS (refined), colmap-lidar and LIDAR-only."""
    out = []
    for cell in cells:
        cell_dir = os.path.join(work, cell)
        if not os.path.exists(os.path.join(cell_dir, "dataset", "poses_gt.txt")):
            continue
        row = [cell]
        for region, _ in REGIONS:
            for prefix in ("run*/openmvs/scene_refined", "ours_run*/mesh", "ours_run*/lidar_poisson"):
                row.append(" / ".join(median_worst(mesh_values(cell_dir, prefix, region, t), min, 3)
                                      for t in (0.05, 0.1, 0.5)))
        out.append("| " + " | ".join(row) + " |")
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--work", required=True)
    parser.add_argument("--cells", required=True)
    parser.add_argument("--summary", action="store_true",
                        help="one row per cell instead of a table per cell")
    args = parser.parse_args()
    cells = args.cells.split(",")
    if args.summary:
        print("| cell | colmap-lidar images | images registered by OpenMVG global, global + priors, "
              "incremental, incremental + priors; stock mapper | "
              + " | ".join(f"{name}: OpenMVG best; stock mapper; colmap-lidar"
                           for _, name, _, _ in POSE_KEYS) + " |")
        print("|" + "---|" * (3 + len(POSE_KEYS)))
        print("\n".join(summary_pose_rows(args.work, cells)))
        print()
        print("| cell | " + " | ".join(
            f"{name}: {method}" for _, name in REGIONS
            for method in ("OpenMVG + OpenMVS (refined)", "colmap-lidar", "LIDAR-only Poisson"))
            + " |")
        print("|" + "---|" * 7)
        print("\n".join(summary_mesh_rows(args.work, cells)))
        return
    for cell in cells:
        cell_dir = os.path.join(args.work, cell)
        dataset = os.path.join(cell_dir, "dataset")
        if not os.path.exists(os.path.join(dataset, "poses_gt.txt")):
            print(f"{cell}: no ground truth", file=sys.stderr)
            continue
        print(f"\n### {cell}\n")
        print("| method | runs | images registered | Table I: position error, baselines sim3 to the "
              "priors, ours unaligned, m | position after sim3 to the truth (centres + axes), cm | "
              "rotation, deg | per step: translation, mm | per step: rotation, deg |")
        print("|---|---|---|---|---|---|---|---|")
        print("\n".join(pose_rows(cell_dir, dataset)))
        print()
        header = ["mesh", "runs"]
        for _, name in REGIONS:
            for icp in ("", " after ICP"):
                header += [f"{name}{icp}: F @0.05", "F @0.1", "F @0.5", "precision @0.5"]
        print("| " + " | ".join(header) + " |")
        print("|" + "---|" * len(header))
        print("\n".join(mesh_rows(cell_dir)))


if __name__ == "__main__":
    main()
