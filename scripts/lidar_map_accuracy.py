#!/usr/bin/env python3
"""How well do a model's poses place the LIDAR scans on the true surface?

A synthetic cell (colmap-lidar synthesize) has the survey (reference.ply) and
the true poses. This script places every frame's scan with the poses of one
or more sparse models (world_from_cam * cam_from_lidar), carries each model
onto the ground truth by the fit of the cameras' centres and axes (as the
mesh and pose evaluators do, src/eval/pose_alignment.h, axes weight 1, no
scale) and prints the share of the scan points within 1, 2 and 5 cm of the
survey, for the ground (|z| < 0.15 m: the synthetic scenes' ground is z = 0)
and for the rest. With --per_frame it also prints each camera's pitch error
(rotation about its x axis, degrees) and height error (cm) after the fit.
The true poses give the floor the range noise leaves.

It separates what the poses do to the LIDAR map from what meshing does: a
height wave along a straight trajectory keeps consecutive scans consistent
(the map looks crisp) while the ground of the whole map leaves the survey.

Usage: python3 scripts/lidar_map_accuracy.py --dataset DIR --ground_truth MODEL
         MODEL [MODEL ...] [--per_frame] [--stride 3]
  dataset       the cell's dataset (reference.ply, calibration.yaml, lidar/)
  ground_truth  a sparse model with the true poses (the matrix's
                gt/workspace/sparse/prior)
  MODEL         sparse models to evaluate (e.g. run1/ws/sparse/refined and
                run1/ws/sparse/lidar_mapper/lidar_graph)
Needs numpy and scipy; runs stock `colmap model_converter`.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

import numpy as np
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

PLY_TYPES = {"float": "<f4", "double": "<f8", "uchar": "u1", "ushort": "<u2",
             "uint": "<u4", "int": "<i4"}


def read_ply_xyz(path):
    with open(path, "rb") as f:
        props, count = [], 0
        while True:
            line = f.readline().decode().strip()
            if line.startswith("element vertex"):
                count = int(line.split()[-1])
            elif line.startswith("property"):
                kind, name = line.split()[1:3]
                props.append((name, PLY_TYPES[kind]))
            elif line == "end_header":
                break
        data = np.frombuffer(f.read(), dtype=np.dtype(props), count=count)
    return np.stack([data["x"], data["y"], data["z"]], 1).astype(float)


def read_model(path):
    """image name -> (world_from_cam rotation matrix, camera centre)."""
    out_dir = tempfile.mkdtemp()
    subprocess.run(["colmap", "model_converter", "--input_path", path,
                    "--output_path", out_dir, "--output_type", "TXT"],
                   check=True, stdout=subprocess.DEVNULL)
    poses = {}
    lines = [l for l in open(os.path.join(out_dir, "images.txt"))
             if not l.startswith("#")]
    for line in lines[::2]:
        t = line.split()
        qw, qx, qy, qz = map(float, t[1:5])
        cam_from_world = Rotation.from_quat([qx, qy, qz, qw]).as_matrix()
        translation = np.array(list(map(float, t[5:8])))
        poses[t[9]] = (cam_from_world.T, -cam_from_world.T @ translation)
    return poses


def cam_from_lidar(dataset):
    text = open(os.path.join(dataset, "calibration.yaml")).read()
    m = re.search(r"cam_from_lidar:.*?\n((?:\s+- \[.*\]\n){4})", text)
    if not m:
        sys.exit(f"lidar_map_accuracy: no cam_from_lidar in {dataset}/calibration.yaml")
    rows = [list(map(float, re.findall(r"-?\d[\d.e+-]*", l.split("[")[1])))
            for l in m.group(1).strip().split("\n")]
    return np.array(rows)


def align_centres_and_axes(centres, rotations, centres_gt, rotations_gt):
    """Rotation and translation (se3) as src/eval/pose_alignment.h, weight 1."""
    xm, ym = centres.mean(0), centres_gt.mean(0)
    sx = np.sqrt(((centres - xm) ** 2).sum(1).mean())
    sy = np.sqrt(((centres_gt - ym) ** 2).sum(1).mean())
    h = (centres_gt - ym).T @ (centres - xm) / (len(centres) * sx * sy)
    h += sum(g @ e.T for g, e in zip(rotations_gt, rotations)) / len(centres)
    u, _, vt = np.linalg.svd(h)
    d = np.eye(3)
    d[2, 2] = np.sign(np.linalg.det(u @ vt))
    rotation = u @ d @ vt
    return rotation, ym - rotation @ xm


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--dataset", required=True)
    parser.add_argument("--ground_truth", required=True)
    parser.add_argument("models", nargs="+")
    parser.add_argument("--per_frame", action="store_true")
    parser.add_argument("--stride", type=int, default=3,
                        help="every n-th point of each scan (default 3)")
    args = parser.parse_args()
    tree = cKDTree(read_ply_xyz(os.path.join(args.dataset, "reference.ply")))
    lidar_to_cam = cam_from_lidar(args.dataset)
    gt = read_model(args.ground_truth)
    names = sorted(gt)
    scans = {}
    for name in names:
        path = os.path.join(args.dataset, "lidar", os.path.splitext(name)[0] + ".ply")
        scans[name] = read_ply_xyz(path)[::args.stride]
    print("| model | within 1 / 2 / 5 cm | ground within 2 / 5 cm | rest within 2 / 5 cm |")
    print("|---|---|---|---|")
    for model_path in [args.ground_truth] + args.models:
        model = read_model(model_path)
        missing = [n for n in names if n not in model]
        if missing:
            print(f"| {model_path} | {len(missing)} frames missing | | |")
            continue
        rotations = [model[n][0] for n in names]
        centres = np.array([model[n][1] for n in names])
        rotations_gt = [gt[n][0] for n in names]
        centres_gt = np.array([gt[n][1] for n in names])
        rotation, translation = align_centres_and_axes(
            centres, rotations, centres_gt, rotations_gt)
        points = []
        for name, world_from_cam, centre in zip(names, rotations, centres):
            in_cam = scans[name] @ lidar_to_cam[:3, :3].T + lidar_to_cam[:3, 3]
            in_world = in_cam @ world_from_cam.T + centre
            points.append(in_world @ rotation.T + translation)
        points = np.concatenate(points)
        dist = tree.query(points, distance_upper_bound=1.0)[0]
        ground = np.abs(points[:, 2]) < 0.15
        share = lambda mask, t: 100.0 * (dist[mask] < t).mean()
        every = np.ones(len(dist), bool)
        print(f"| {model_path} | {share(every, 0.01):.1f} / {share(every, 0.02):.1f} / "
              f"{share(every, 0.05):.1f} % | {share(ground, 0.02):.1f} / "
              f"{share(ground, 0.05):.1f} % | {share(~ground, 0.02):.1f} / "
              f"{share(~ground, 0.05):.1f} % |")
        if args.per_frame:
            pitch = [np.degrees(Rotation.from_matrix(g.T @ rotation @ e).as_rotvec()[0])
                     for g, e in zip(rotations_gt, rotations)]
            height = (centres @ rotation.T + translation - centres_gt)[:, 2] * 100
            print("  pitch error, deg: " + " ".join(f"{p:.3f}" for p in pitch))
            print("  height error, cm: " + " ".join(f"{h:.1f}" for h in height))


if __name__ == "__main__":
    main()
