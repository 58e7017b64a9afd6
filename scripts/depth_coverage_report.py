#!/usr/bin/env python3
"""Where the depth maps of a synthetic cell lack coverage, and why.

Splits the surface pixels of every frame (ground-truth depth > 0) by how
many other frames see the same point (ground-truth poses and depth maps: the
point projects inside the frame's image and its true depth there agrees
within 2 %) and by whether the point lies inside the LIDAR's vertical field
of view from the frame's own scan position (calibration.yaml's
lidar.vertical_fov_deg), and prints per class its share of the surface
pixels and the share our maps cover. A point that no other frame sees can
only get a depth from the LIDAR; one outside the LIDAR's field only from
photometry. With --by_depth, also per depth range: the share with a
photometric depth and with a geometric (filtered) one.

Usage: /usr/bin/python3 scripts/depth_coverage_report.py --workspace WS
         --dataset DATASET [--by_depth]
  WS       the pipeline's workspace (WS/dense/stereo/depth_maps)
  DATASET  the synthetic recording (calibration.yaml, poses_gt.txt,
           ground_truth/depth_maps; colmap-lidar synthesize)
Cameras without distortion only (PINHOLE, SIMPLE_PINHOLE). Needs numpy
(Debian: python3-numpy).
"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from observed_crease_edges import read_calibration, read_mat, read_poses  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--workspace', required=True)
    parser.add_argument('--dataset', required=True)
    parser.add_argument('--by_depth', action='store_true')
    args = parser.parse_args()
    calib_path = os.path.join(args.dataset, 'calibration.yaml')
    if 'vertical_fov_deg' not in open(calib_path).read():
        sys.exit(f'{calib_path} has no lidar.vertical_fov_deg')
    calib = read_calibration(calib_path)  # PINHOLE / SIMPLE_PINHOLE only
    fx, fy, cx, cy = calib['K']
    width, height = int(calib['width']), int(calib['height'])
    lidar_from_cam = np.linalg.inv(calib['cam_from_lidar'])
    poses = read_poses(os.path.join(args.dataset, 'poses_gt.txt'))  # world_from_cam
    names = sorted(poses)
    truth = {n: read_mat(os.path.join(args.dataset, 'ground_truth/depth_maps',
                                      f'{n}.bin')) for n in names}
    maps_dir = os.path.join(args.workspace, 'dense/stereo/depth_maps')
    cols, rows = np.meshgrid(np.arange(width), np.arange(height))
    classes = ['seen by no other frame, in the LIDAR field',
               'seen by no other frame, outside it',
               'seen by 1 other frame, in the LIDAR field',
               'seen by 1 other frame, outside it',
               'seen by 2+ other frames, in the LIDAR field',
               'seen by 2+ other frames, outside it']
    total = np.zeros(len(classes))
    covered = np.zeros(len(classes))
    bins = [0, 5, 10, 20, 40, np.inf]
    by_depth = np.zeros((2, len(bins) - 1, 3))
    for name in names:
        depth = truth[name]
        valid = depth > 0
        ours = read_mat(os.path.join(maps_dir, f'{name}.png.geometric.bin'))[valid] > 0
        point_in_cam = np.stack([(cols - cx) / fx * depth, (rows - cy) / fy * depth,
                                 depth], -1)[valid]
        rotation, centre = poses[name]
        point_in_world = point_in_cam @ rotation.T + centre
        num_seen = np.zeros(len(point_in_world), int)
        for other in names:
            if other == name:
                continue
            r, c = poses[other]
            p = (point_in_world - c) @ r
            z = p[:, 2]
            ok = z > 0.1
            u = np.full(len(z), -1)
            v = np.full(len(z), -1)
            u[ok] = np.round(p[ok, 0] / z[ok] * fx + cx).astype(int)
            v[ok] = np.round(p[ok, 1] / z[ok] * fy + cy).astype(int)
            ok &= (u >= 0) & (u < width) & (v >= 0) & (v < height)
            seen_depth = np.zeros(len(z))
            seen_depth[ok] = truth[other][v[ok], u[ok]]
            num_seen += ok & (np.abs(seen_depth - z) < 0.02 * z)
        point_in_lidar = point_in_cam @ lidar_from_cam[:3, :3].T + lidar_from_cam[:3, 3]
        elevation = np.degrees(np.arctan2(point_in_lidar[:, 2],
                                          np.hypot(point_in_lidar[:, 0], point_in_lidar[:, 1])))
        in_field = (elevation >= calib['fov'][0]) & (elevation <= calib['fov'][1])
        seen_class = np.minimum(num_seen, 2)
        for k in range(len(classes)):
            selected = (seen_class == k // 2) & (in_field == (k % 2 == 0))
            total[k] += selected.sum()
            covered[k] += (selected & ours).sum()
        if args.by_depth:
            photometric = read_mat(os.path.join(
                maps_dir, f'{name}.png.photometric.bin'))[valid] > 0
            d = depth[valid]
            for b in range(len(bins) - 1):
                for lidar in (0, 1):
                    selected = (d >= bins[b]) & (d < bins[b + 1]) & (in_field == bool(lidar))
                    by_depth[lidar, b] += [selected.sum(), (selected & photometric).sum(),
                                           (selected & ours).sum()]
    print(f'coverage {100 * covered.sum() / total.sum():.1f} % of '
          f'{int(total.sum())} surface pixels, {len(names)} frames')
    print('| surface pixels | share % | covered % |')
    print('|---|---|---|')
    for k, label in enumerate(classes):
        print(f'| {label} | {100 * total[k] / total.sum():.1f} | '
              f'{100 * covered[k] / max(total[k], 1):.1f} |')
    if args.by_depth:
        print()
        print('| LIDAR field | depth, m | share % | photometric % | geometric % |')
        print('|---|---|---|---|---|')
        for lidar in (1, 0):
            for b in range(len(bins) - 1):
                n, photo, geo = by_depth[lidar, b]
                if n == 0:
                    continue
                print(f'| {"in" if lidar else "outside"} | {bins[b]:g}-{bins[b + 1]:g} | '
                      f'{100 * n / total.sum():.1f} | {100 * photo / n:.1f} | {100 * geo / n:.1f} |')


if __name__ == '__main__':
    main()
