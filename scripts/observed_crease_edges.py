#!/usr/bin/python3
"""Crease edges of a synthetic dataset observed by both sensors (approximation).

The line detection module (paper section III-B) only lifts lines seen by the
camera *and* the LIDAR, so its recall is measured against the ground-truth
crease edges (ground_truth/crease_edges.txt) that some frame observes with
both sensors. An edge counts as observed when, for at least one frame, its
midpoint
  * projects into the image and is not hidden: the ground-truth depth map of
    that frame (ground_truth/depth_maps/<frame>.bin, COLMAP Mat float32,
    camera z-depth of the ray through pixel (col, row) without +0.5, the MVS
    convention) has, in the 3x3 pixels around the projection, a depth within
    depth_tolerance_abs + depth_tolerance_rel * z of the midpoint's depth z;
  * lies within the LIDAR's vertical field of view (calibration.yaml
    lidar.vertical_fov_deg, default +-16.6 deg) and range, seen from that
    frame's LIDAR origin: p_lidar = inverse(cam_from_lidar) * cam_from_world
    * p_world (calibration.yaml cam_from_lidar maps LIDAR to camera points).
LIDAR occlusion is not tested (the camera's depth map stands in for it; the
two sensors are 10 cm apart). Writes the observed edges' lines of
crease_edges.txt (same format) to --output and prints a one-line summary.
"""
import argparse
import os
import sys

import numpy as np


def read_calibration(path):
    """Parses the few keys needed from calibration.yaml (no yaml module)."""
    calib = {"fov": (-16.6, 16.6)}
    rows = []
    section = None
    with open(path) as f:
        for raw in f:
            line = raw.split("#")[0].rstrip()
            if not line.strip():
                continue
            if not line.startswith(" "):
                section = line.split(":")[0].strip()
                continue
            key, _, value = line.strip().partition(":")
            value = value.strip()
            if section == "camera" and key == "params":
                calib["params"] = [float(v) for v in value.strip("[]").split(",")]
            elif section == "camera" and key in ("width", "height", "model"):
                calib[key] = value
            elif section == "cam_from_lidar" and line.strip().startswith("-"):
                rows.append([float(v) for v in
                             line.strip()[1:].strip().strip("[]").split(",")])
            elif section == "lidar" and key == "vertical_fov_deg":
                calib["fov"] = tuple(float(v) for v in value.strip("[]").split(","))
    if calib.get("model") not in ("PINHOLE", "SIMPLE_PINHOLE"):
        sys.exit(f"ERROR: {path}: camera model {calib.get('model')} is not "
                 "supported (PINHOLE / SIMPLE_PINHOLE)")
    params = calib["params"]
    if calib["model"] == "SIMPLE_PINHOLE":
        params = [params[0], params[0], params[1], params[2]]
    calib["K"] = params
    calib["cam_from_lidar"] = np.array(rows, dtype=float)
    if calib["cam_from_lidar"].shape != (4, 4):
        sys.exit(f"ERROR: {path}: cam_from_lidar must be 4x4")
    return calib


def quat_to_rot(qx, qy, qz, qw):
    q = np.array([qw, qx, qy, qz], dtype=float)
    q /= np.linalg.norm(q)
    w, x, y, z = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def read_poses(path):
    poses = {}
    with open(path) as f:
        for line in f:
            line = line.split("#")[0].split()
            if len(line) != 8:
                continue
            t = np.array([float(v) for v in line[1:4]])
            R = quat_to_rot(*[float(v) for v in line[4:8]])
            poses[line[0]] = (R, t)  # world_from_cam
    return poses


def read_mat(path):
    with open(path, "rb") as f:
        data = f.read()
    header = []
    pos = 0
    for _ in range(3):
        end = data.index(b"&", pos)
        header.append(int(data[pos:end]))
        pos = end + 1
    width, height, channels = header
    values = np.frombuffer(data, dtype="<f4", count=width * height * channels,
                           offset=pos)
    return values.reshape(channels, height, width)[0]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dataset", required=True)
    parser.add_argument("--output", required=True)
    parser.add_argument("--depth_tolerance_abs", type=float, default=0.05)
    parser.add_argument("--depth_tolerance_rel", type=float, default=0.02)
    parser.add_argument("--lidar_max_range", type=float, default=100.0)
    args = parser.parse_args()

    calib = read_calibration(os.path.join(args.dataset, "calibration.yaml"))
    fx, fy, cx, cy = calib["K"]
    lidar_from_cam = np.linalg.inv(calib["cam_from_lidar"])
    min_elev, max_elev = np.radians(calib["fov"][0]), np.radians(calib["fov"][1])
    poses = read_poses(os.path.join(args.dataset, "poses_gt.txt"))

    edge_lines = []
    with open(os.path.join(args.dataset, "ground_truth", "crease_edges.txt")) as f:
        for line in f:
            if line.strip() and not line.lstrip().startswith("#"):
                edge_lines.append(line.rstrip("\n"))
    edges = np.array([[float(v) for v in l.split()[:6]] for l in edge_lines])
    mid = 0.5 * (edges[:, 0:3] + edges[:, 3:6])
    observed = np.zeros(len(edges), dtype=bool)
    depth_dir = os.path.join(args.dataset, "ground_truth", "depth_maps")
    num_frames = 0
    for frame, (R, t) in sorted(poses.items()):
        depth_path = os.path.join(depth_dir, frame + ".bin")
        if not os.path.exists(depth_path):
            continue
        num_frames += 1
        depth = read_mat(depth_path)
        height, width = depth.shape
        p_cam = (mid - t) @ R  # R^T (p - t) for each row
        z = p_cam[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            u = fx * p_cam[:, 0] / z + cx
            v = fy * p_cam[:, 1] / z + cy
        # MVS convention: depth sample (col, row) is image point (col, row).
        col = np.rint(u)
        row = np.rint(v)
        seen = (z > 0) & (col >= 0) & (col < width) & (row >= 0) & (row < height)
        idx = np.nonzero(seen)[0]
        ci = col[idx].astype(int)
        ri = row[idx].astype(int)
        tol = args.depth_tolerance_abs + args.depth_tolerance_rel * z[idx]
        visible = np.zeros(len(idx), dtype=bool)
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                rr = np.clip(ri + dr, 0, height - 1)
                cc = np.clip(ci + dc, 0, width - 1)
                d = depth[rr, cc]
                visible |= (d > 0) & (np.abs(d - z[idx]) <= tol)
        idx = idx[visible]
        p_lidar = p_cam[idx] @ lidar_from_cam[:3, :3].T + lidar_from_cam[:3, 3]
        elevation = np.arctan2(p_lidar[:, 2], np.hypot(p_lidar[:, 0], p_lidar[:, 1]))
        in_fov = ((elevation >= min_elev) & (elevation <= max_elev) &
                  (np.linalg.norm(p_lidar, axis=1) <= args.lidar_max_range))
        observed[idx[in_fov]] = True

    lengths = np.linalg.norm(edges[:, 3:6] - edges[:, 0:3], axis=1)
    with open(args.output, "w") as f:
        f.write("# Crease edges observed by both sensors (scripts/"
                "observed_crease_edges.py), format of crease_edges.txt\n")
        for line, keep in zip(edge_lines, observed):
            if keep:
                f.write(line + "\n")
    print(f"Observed by both sensors: {observed.sum()} of {len(edges)} crease "
          f"edges, {lengths[observed].sum():.1f} of {lengths.sum():.1f} m "
          f"({num_frames} frames)")


if __name__ == "__main__":
    main()
