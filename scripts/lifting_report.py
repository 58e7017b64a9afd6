#!/usr/bin/python3
"""Why LSD segments were or were not lifted, against a synthetic ground truth.

Issue 15 asks for many, correct 3D segments on every sensor. This script says
where the 2D segments go: it reads the per-segment outcomes that
`colmap-lidar line_extractor --debug_path P` writes (P/<stem>.json, see
src/lines/debug_overlay.h) and classifies each LSD segment with the frame's
ground-truth depth map (ground_truth/depth_maps/<stem>.bin, camera z-depth
of the ray through pixel (col, row), COLMAP's MVS convention, 0 where the
ray hits nothing):
  - the points of the depth map in a band on each side of the segment
    (offsets band_min_px..band_max_px along its normal, samples along its
    middle 80 %) are back-projected and a plane is fitted per side;
  - "sky": one side has fewer than half its samples on a surface;
  - "depth_edge": the two planes' depths along the segment's rays differ by
    more than max(5 cm, 2 %) (an occluding contour or a step);
  - "crease": the planes' normals differ by 20 deg or more;
  - "flat": one surface on both sides (a texture line: joints, paint,
    shadows, window panes' reflections);
  - "rough": a side's plane residual is large (foliage, curved surfaces).
A segment is "in the LIDAR's field" when its midpoint on the nearer plane
lies within the vertical field of view (calibration.yaml) seen from the
LIDAR. A lifted segment is "near the surface" when both 3D endpoints lie
within 5 cm of a ground-truth point of the 9 x 9 pixels around their
projections.

Prints, per class, the segments per frame, those in the LIDAR's field, the
lifted ones (and those near the surface) and the outcomes of the segments in
the LIDAR's field (lifted by edge points / by planes, or why not: the edge
points' reason / the planes' reason), and with --json the same as JSON.

Usage: scripts/lifting_report.py --dataset DIR --debug_path DIR [--json F]
"""
import argparse
import collections
import glob
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from observed_crease_edges import read_calibration, read_mat  # noqa: E402

BAND_MIN_PX = 3.0
BAND_MAX_PX = 9.0
NUM_ALONG = 9
MIN_STEP_M = 0.05
MIN_STEP_REL = 0.02
MIN_CREASE_DEG = 20.0


class View:
    def __init__(self, depth, K):
        self.depth = depth
        self.fx, self.fy, self.cx, self.cy = K
        self.h, self.w = depth.shape

    def points(self, pixels):
        """3D points (camera frame) at pixels (N x 2, COLMAP convention);
        rows with no surface are NaN."""
        cols = np.rint(pixels[:, 0]).astype(int)
        rows = np.rint(pixels[:, 1]).astype(int)
        ok = (cols >= 0) & (cols < self.w) & (rows >= 0) & (rows < self.h)
        z = np.zeros(len(pixels))
        z[ok] = self.depth[rows[ok], cols[ok]]
        z[z <= 0] = np.nan
        x = (cols - self.cx) / self.fx
        y = (rows - self.cy) / self.fy
        return np.stack([x * z, y * z, z], axis=1)

    def ray(self, pixel):
        return np.array([(pixel[0] - self.cx) / self.fx,
                         (pixel[1] - self.cy) / self.fy, 1.0])


def fit_plane(points):
    centre = points.mean(axis=0)
    _, s, vt = np.linalg.svd(points - centre, full_matrices=False)
    normal = vt[2]
    rms = s[2] / np.sqrt(len(points))
    return centre, normal, rms


def classify(view, start, end, fov, lidar_from_cam):
    direction = end - start
    length = np.linalg.norm(direction)
    if length < 1e-6:
        return "rough", False
    direction /= length
    normal2d = np.array([-direction[1], direction[0]])
    ts = np.linspace(0.1, 0.9, NUM_ALONG)
    offsets = np.arange(BAND_MIN_PX, BAND_MAX_PX + 0.5, 1.0)
    along = start[None, :] + ts[:, None] * (end - start)[None, :]
    sides = []
    for sign in (1.0, -1.0):
        pixels = (along[:, None, :] + sign * offsets[None, :, None] *
                  normal2d[None, None, :]).reshape(-1, 2)
        pts = view.points(pixels)
        good = pts[~np.isnan(pts[:, 0])]
        sides.append((good, len(pixels)))
    if any(len(good) < 0.5 * total for good, total in sides):
        near = max(sides, key=lambda s: len(s[0]))[0]
        return "sky", in_field(near.mean(axis=0) if len(near) else None,
                               fov, lidar_from_cam)
    planes = [fit_plane(good) for good, _ in sides]
    # Depth of each side's plane along the segment's rays.
    depths = []
    for centre, n, _ in planes:
        row = []
        for p in along:
            r = view.ray(p)
            d = n @ r
            row.append(np.nan if abs(d) < 1e-6 else (n @ centre) / d)
        depths.append(np.array(row))
    za, zb = depths
    step = np.nanmedian(np.abs(za - zb))
    zmin = np.nanmedian(np.minimum(za, zb))
    near_side = 0 if np.nanmedian(za) <= np.nanmedian(zb) else 1
    mid_ray = view.ray(0.5 * (start + end))
    mid_point = mid_ray * np.nanmedian(depths[near_side])
    field = in_field(mid_point, fov, lidar_from_cam)
    if not np.isfinite(step):
        return "rough", field
    if step > max(MIN_STEP_M, MIN_STEP_REL * zmin):
        return "depth_edge", field
    if max(p[2] for p in planes) > max(0.01, 0.004 * zmin):
        return "rough", field
    angle = np.degrees(np.arccos(min(1.0, abs(planes[0][1] @ planes[1][1]))))
    return ("crease" if angle >= MIN_CREASE_DEG else "flat"), field


def in_field(point_in_cam, fov, lidar_from_cam):
    if point_in_cam is None or not np.all(np.isfinite(point_in_cam)):
        return False
    p = lidar_from_cam[:3, :3] @ point_in_cam + lidar_from_cam[:3, 3]
    elevation = np.degrees(np.arctan2(p[2], np.hypot(p[0], p[1])))
    return fov[0] <= elevation <= fov[1]


def endpoint_error(view, K, point):
    if point[2] <= 0:
        return np.inf
    u = K[0] * point[0] / point[2] + K[2]
    v = K[1] * point[1] / point[2] + K[3]
    grid = np.array([(u + du, v + dv) for du in range(-4, 5)
                     for dv in range(-4, 5)])
    pts = view.points(grid)
    pts = pts[~np.isnan(pts[:, 0])]
    if len(pts) == 0:
        return np.inf
    return float(np.min(np.linalg.norm(pts - point[None, :], axis=1)))


def outcome_of(segment):
    if segment["edge_result"] == "lifted":
        return "lifted_by_edges"
    if segment["plane_result"] in ("crease", "occlusion"):
        return "lifted_by_planes_" + segment["plane_result"]
    if segment["plane_result"] != "not_tried":
        return "edges:" + segment["edge_result"] + "/planes:" + \
            segment["plane_result"]
    return "edges:" + segment["edge_result"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--dataset", required=True)
    parser.add_argument("--debug_path", required=True)
    parser.add_argument("--json", default="")
    args = parser.parse_args()
    calib = read_calibration(os.path.join(args.dataset, "calibration.yaml"))
    K = calib["K"]
    lidar_from_cam = np.linalg.inv(calib["cam_from_lidar"])
    files = sorted(glob.glob(os.path.join(args.debug_path, "*.json")))
    if not files:
        sys.exit(f"ERROR: no <image>.json in {args.debug_path} (run "
                 "line_extractor with --debug_path)")
    counts = collections.Counter()
    in_field_counts = collections.Counter()
    outcomes = collections.defaultdict(collections.Counter)
    lifted_near = collections.Counter()
    lifted_all = collections.Counter()
    for path in files:
        stem = os.path.splitext(os.path.basename(path))[0]
        depth_path = os.path.join(args.dataset, "ground_truth", "depth_maps",
                                  stem + ".bin")
        if not os.path.exists(depth_path):
            sys.exit(f"ERROR: {depth_path} not found (a synthetic dataset's "
                     "ground truth is needed)")
        view = View(read_mat(depth_path), K)
        with open(path) as f:
            report = json.load(f)
        for segment in report["segments"]:
            start = np.array(segment["start"], dtype=float)
            end = np.array(segment["end"], dtype=float)
            label, field = classify(view, start, end, calib["fov"],
                                    lidar_from_cam)
            counts[label] += 1
            in_field_counts[label] += int(field)
            outcome = outcome_of(segment)
            if field:
                outcomes[label][outcome] += 1
            if "start3D_in_cam" in segment:
                lifted_all[label] += 1
                errors = [endpoint_error(view, K, np.array(segment[k]))
                          for k in ("start3D_in_cam", "end3D_in_cam")]
                if max(errors) <= 0.05:
                    lifted_near[label] += 1
    num_frames = len(files)
    total = sum(counts.values())
    print(f"{num_frames} frames, {total / num_frames:.1f} LSD segments per "
          "frame")
    print("| class | per frame | in the LIDAR's field | lifted (within 5 cm "
          "of the surface) | outcomes in the LIDAR's field |")
    print("|---|---|---|---|---|")
    result = {"num_frames": num_frames, "classes": {}}
    for label in ("crease", "depth_edge", "sky", "flat", "rough"):
        n = counts[label]
        if n == 0:
            continue
        n_field = in_field_counts[label]
        top = ", ".join(f"{k} {100.0 * v / max(1, n_field):.0f} %"
                        for k, v in outcomes[label].most_common(5))
        print(f"| {label} | {n / num_frames:.1f} | "
              f"{n_field / num_frames:.1f} | "
              f"{lifted_all[label] / num_frames:.1f} "
              f"({lifted_near[label] / num_frames:.1f}) | {top} |")
        result["classes"][label] = {
            "per_frame": n / num_frames,
            "in_lidar_field_per_frame": n_field / num_frames,
            "lifted_per_frame": lifted_all[label] / num_frames,
            "lifted_near_surface_per_frame": lifted_near[label] / num_frames,
            "outcomes_in_lidar_field": dict(outcomes[label]),
        }
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=2)


if __name__ == "__main__":
    main()
