#!/usr/bin/env python3
"""Markdown tables of scripts/baselines/bench_baselines.sh: per cell, the
OpenMVG variants and colmap-lidar's runs (poses), and OpenMVG + OpenMVS,
colmap-lidar and LIDAR-only Poisson (meshes), each figure the median and the
worst over the runs, "median (worst)".

Poses: images registered; camera position / rotation error after the sim3 of
centres and axes to the ground truth (pose_evaluator); and the paper's Table
I protocol, computed here from the models: the baselines sim3-aligned to the
noisy prior centres (Umeyama), colmap-lidar unaligned, then the mean position
error against the ground truth.
Meshes: F-score at 0.05, 0.1 and 0.5 m and precision at 0.5 m, after the
alignment by the model's cameras and after ICP (mesh_evaluator).

Usage: baselines_table.py --work DIR --cells a,b [--summary]
  --summary  one row per cell: the OpenMVG variant that registered the most
             images beside colmap-lidar, and the meshes' F after ICP
"""
import argparse
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


def read_centres(model):
    """Camera centres by image name stem of a COLMAP model (text or binary)."""
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


def read_pose_file(path):
    """Centres (world_from_cam translations) by frame of a poses_*.txt."""
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


def paper_position_error(model, dataset, align_to_priors):
    """Mean position error (m) against the ground truth, the model aligned
    to the prior centres by Umeyama's sim3 or not at all."""
    centres = read_centres(model)
    truth = read_pose_file(os.path.join(dataset, "poses_gt.txt"))
    names = sorted(set(centres) & set(truth))
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


def pose_rows(cell_dir, dataset):
    rows = []
    methods = [(f"OpenMVG {v.replace('_', ' + ')}", f"openmvg_{v}", True)
               for v in ("global", "global_priors", "incremental", "incremental_priors")]
    for label, name, baseline in methods:
        runs = sorted(glob.glob(os.path.join(cell_dir, "baselines", "run*", name)))
        rows.append((label, runs, baseline))
    ours = sorted(glob.glob(os.path.join(cell_dir, "baselines", "ours_run*")))
    rows.append(("colmap-lidar (default)", ours, False))
    out = []
    for label, runs, baseline in rows:
        registered, position, rotation, paper = [], [], [], []
        for run in runs:
            result = load(os.path.join(run, "poses.json"))
            if result is None:
                registered.append(0)
                continue
            registered.append(result["num_matched"])
            position.append(100 * result["position_error_m"]["mean"])
            rotation.append(result["rotation_error_deg"]["mean"])
            model = (os.path.join(run, "colmap") if baseline else
                     os.path.join(cell_dir, os.path.basename(run).replace("ours_", ""),
                                  "ws", "sparse", "refined"))
            paper.append(paper_position_error(model, dataset, baseline))
        total = len(read_pose_file(os.path.join(dataset, "poses_gt.txt")))
        out.append(f"| {label} | {len(runs)} | {median_worst(registered, min, 0)} / {total} | "
                   f"{median_worst(paper, max, 3)} | {median_worst(position)} | "
                   f"{median_worst(rotation, max, 3)} |")
    return out


def mesh_rows(cell_dir):
    rows = [("OpenMVG + OpenMVS (mesh)", "run*/openmvs/scene_mesh_eval"),
            ("OpenMVG + OpenMVS (refined)", "run*/openmvs/scene_refined_eval"),
            ("colmap-lidar (default)", "ours_run*/mesh_eval"),
            ("LIDAR-only Poisson", "ours_run*/lidar_poisson_eval")]
    out = []
    for label, pattern in rows:
        paths = sorted(glob.glob(os.path.join(cell_dir, "baselines", pattern + ".json")))
        cells = []
        for suffix in ("", "_icp"):
            f = {0.05: [], 0.1: [], 0.5: []}
            precision = []
            for path in paths:
                result = load(path.replace(".json", suffix + ".json"))
                if result is None:
                    continue
                scores = dict(zip(result["thresholds_m"], result["fscore"]))
                for t in f:
                    f[t].append(scores.get(t))
                precision.append(dict(zip(result["thresholds_m"], result["precision"])).get(0.5))
            cells += [median_worst(f[t], min, 3) for t in (0.05, 0.1, 0.5)]
            cells.append(median_worst(precision, min, 3))
        if "OpenMVS" in label:
            # The OpenMVG variant each run's OpenMVS worked on.
            used = []
            for path in paths:
                variant = os.path.join(os.path.dirname(path), "openmvg_variant.txt")
                if os.path.exists(variant):
                    used.append(os.path.basename(open(variant).read().strip())
                                .replace("openmvg_", "").replace("_", " + "))
            if used:
                label += " on OpenMVG " + ", ".join(used)
        out.append(f"| {label} | {len(paths)} | " + " | ".join(cells) + " |")
    return out


def summary_rows(work, cells):
    """One row per cell: the OpenMVG variant that registered the most images
    (median over its runs) beside colmap-lidar, and the meshes' F."""
    out = []
    for cell in cells:
        cell_dir = os.path.join(work, cell)
        dataset = os.path.join(cell_dir, "dataset")
        if not os.path.exists(os.path.join(dataset, "poses_gt.txt")):
            continue
        total = len(read_pose_file(os.path.join(dataset, "poses_gt.txt")))
        best = None
        for variant in ("global", "global_priors", "incremental", "incremental_priors"):
            results = [load(os.path.join(r, "poses.json")) for r in sorted(
                glob.glob(os.path.join(cell_dir, "baselines", "run*", "openmvg_" + variant)))]
            registered = [r["num_matched"] if r else 0 for r in results]
            if registered and (best is None or np.median(registered) > np.median(best[1])):
                best = (variant, registered, [r for r in results if r])
        ours = [load(p) for p in sorted(glob.glob(
            os.path.join(cell_dir, "baselines", "ours_run*", "poses.json")))]
        ours = [r for r in ours if r]

        def f_of(pattern, threshold):
            values = []
            for path in sorted(glob.glob(os.path.join(cell_dir, "baselines", pattern))):
                result = load(path)
                if result:
                    values.append(dict(zip(result["thresholds_m"], result["fscore"])).get(threshold))
            return median_worst(values, min, 3)

        mvg = "-"
        if best:
            variant, registered, results = best
            mvg = (f"{variant.replace('_', ' + ')}: {median_worst(registered, min, 0)} / {total}, "
                   f"{median_worst([100 * r['position_error_m']['mean'] for r in results])} cm, "
                   f"{median_worst([r['rotation_error_deg']['mean'] for r in results], max, 3)} deg")
        mine = (f"{median_worst([r['num_matched'] for r in ours], min, 0)} / {total}, "
                f"{median_worst([100 * r['position_error_m']['mean'] for r in ours])} cm, "
                f"{median_worst([r['rotation_error_deg']['mean'] for r in ours], max, 3)} deg")
        meshes = " | ".join(
            " / ".join(f_of(pattern, t) for t in (0.05, 0.1, 0.5))
            for pattern in ("run*/openmvs/scene_refined_eval_icp.json",
                            "ours_run*/mesh_eval_icp.json",
                            "ours_run*/lidar_poisson_eval_icp.json"))
        out.append(f"| {cell} | {mvg} | {mine} | {meshes} |")
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--work", required=True)
    parser.add_argument("--cells", required=True)
    parser.add_argument("--summary", action="store_true",
                        help="one row per cell instead of a table per cell")
    args = parser.parse_args()
    if args.summary:
        print("| cell | OpenMVG, the variant registering the most: images, position / rotation after "
              "sim3 to the truth | colmap-lidar: images, position / rotation | mesh F @0.05 / 0.1 / 0.5 m "
              "after ICP: OpenMVG + OpenMVS (refined) | colmap-lidar | LIDAR-only Poisson |")
        print("|---|---|---|---|---|---|")
        print("\n".join(summary_rows(args.work, args.cells.split(","))))
        return
    for cell in args.cells.split(","):
        cell_dir = os.path.join(args.work, cell)
        dataset = os.path.join(cell_dir, "dataset")
        if not os.path.exists(os.path.join(dataset, "poses_gt.txt")):
            print(f"{cell}: no ground truth", file=sys.stderr)
            continue
        print(f"\n### {cell}\n")
        print("| method | runs | images registered | Table I: position error, baselines sim3 to the priors, "
              "ours unaligned, m | position after sim3 to the truth (centres + axes), cm | rotation, deg |")
        print("|---|---|---|---|---|---|")
        print("\n".join(pose_rows(cell_dir, dataset)))
        print()
        print("| mesh | runs | F @0.05 | F @0.1 | F @0.5 | precision @0.5 | after ICP: F @0.05 | F @0.1 | "
              "F @0.5 | precision @0.5 |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        print("\n".join(mesh_rows(cell_dir)))


if __name__ == "__main__":
    main()
