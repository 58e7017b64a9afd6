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
photometric depth and with a geometric (filtered) one. With --by_texture,
also by the image's texture around the pixel (standard deviation of the
grey values in [0, 1] over a 9 x 9 window, PatchMatch's NCC window): below
0.005 the patch's variance is under the NCC cost's floor (kMinVariance in
src/mvs/ncc_cost.cc), and only the LIDAR can give such a pixel a depth.
With --by_error, where the covered pixels more than 5 cm off along the ray
lie: at a depth edge of the truth (its depths over 7 x 7 pixels spanning
more than 5 %), at grazing incidence (the ray within 14 deg of the true
surface), elsewhere; by depth; and how many carry the true depth (within 5
cm) of a pixel at most 1 or 2 pixels away (a boundary placed off). With
--lidar, per depth range, the share of the frame's own LIDAR points (its
scan, placed with the true pose and calibration) whose depth is within 5 cm
of the truth at their sub-pixel projection (bilinear; skipped where the 2 x 2
truth pixels span more than 5 % of depth), the same for the other frames'
scans placed with the true poses (what the fused cloud holds, without its
pose error), beside the share of our covered pixels within 5 cm: the
sensor's own accuracy along the camera's ray, and what range noise along
another scanner's ray becomes when the camera sees the surface at an angle.

Usage: /usr/bin/python3 scripts/depth_coverage_report.py --workspace WS
         --dataset DATASET [--by_depth] [--by_texture] [--by_error] [--lidar]
  WS       the pipeline's workspace (WS/dense/stereo/depth_maps)
  DATASET  the synthetic recording (calibration.yaml, poses_gt.txt,
           ground_truth/depth_maps; colmap-lidar synthesize)
Cameras without distortion only (PINHOLE, SIMPLE_PINHOLE). Needs numpy
(Debian: python3-numpy); --by_texture also scipy and PIL (python3-scipy,
python3-pil), --by_error and --lidar scipy.
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
    parser.add_argument('--by_texture', action='store_true')
    parser.add_argument('--by_error', action='store_true')
    parser.add_argument('--lidar', action='store_true')
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
    texture_bins = [0.0, 0.005, 0.02, np.inf]
    by_texture = np.zeros((2, len(texture_bins) - 1, 2))
    errors = ErrorSplit((cols - cx) / fx, (rows - cy) / fy)
    lidar_split = LidarAlongRay(calib, lidar_from_cam, args.dataset) if args.lidar else None
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
        if args.by_error:
            errors.add(depth, read_mat(os.path.join(maps_dir, f'{name}.png.geometric.bin')))
        if args.lidar:
            lidar_split.add(depth, read_mat(os.path.join(maps_dir, f'{name}.png.geometric.bin')),
                            name, poses)
        if args.by_texture:
            texture = local_grey_stddev(
                os.path.join(args.dataset, 'images', f'{name}.png'))[valid]
            for b in range(len(texture_bins) - 1):
                for lidar in (0, 1):
                    selected = ((texture >= texture_bins[b]) &
                                (texture < texture_bins[b + 1]) &
                                (in_field == bool(lidar)))
                    by_texture[lidar, b] += [selected.sum(), (selected & ours).sum()]
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
    if args.by_texture:
        print()
        print('| LIDAR field | grey std over 9x9 | share % | geometric % |')
        print('|---|---|---|---|')
        for lidar in (1, 0):
            for b in range(len(texture_bins) - 1):
                n, geo = by_texture[lidar, b]
                if n == 0:
                    continue
                print(f'| {"in" if lidar else "outside"} | '
                      f'{texture_bins[b]:g}-{texture_bins[b + 1]:g} | '
                      f'{100 * n / total.sum():.1f} | {100 * geo / n:.1f} |')
    if args.by_error:
        print()
        errors.report()
    if args.lidar:
        print()
        lidar_split.report()


class ErrorSplit:
    """Where the covered pixels more than 5 cm off along the ray lie."""
    bins = [0, 5, 10, 20, np.inf]

    def __init__(self, x, y):
        ray = np.stack([x, y, np.ones_like(x)], -1)
        self.ray = ray / np.linalg.norm(ray, axis=-1, keepdims=True)
        self.x, self.y = x, y
        self.counts = {}

    def _add(self, key, value):
        self.counts[key] = self.counts.get(key, 0) + int(value)

    def add(self, truth, ours):
        from scipy.ndimage import maximum_filter, minimum_filter  # noqa: E402
        valid = (truth > 0) & (ours > 0)
        off = valid & (np.abs(ours - truth) > 0.05)
        spread = (maximum_filter(np.where(truth > 0, truth, 0.0), size=7) /
                  np.maximum(minimum_filter(np.where(truth > 0, truth, 1e9), size=7), 1e-6))
        edge = spread > 1.05
        points = np.stack([self.x * truth, self.y * truth, truth], -1)
        normal = np.cross(np.gradient(points, axis=1), np.gradient(points, axis=0))
        normal /= np.linalg.norm(normal, axis=-1, keepdims=True) + 1e-12
        grazing = np.abs((normal * self.ray).sum(-1)) < 0.25
        self._add('covered', valid.sum())
        self._add('off', off.sum())
        self._add('edge', (off & edge).sum())
        self._add('grazing', (off & ~edge & grazing).sum())
        for b in range(len(self.bins) - 1):
            selected = (truth >= self.bins[b]) & (truth < self.bins[b + 1])
            self._add(f'covered{b}', (valid & selected).sum())
            self._add(f'off{b}', (off & selected).sum())
        rows, cols = np.nonzero(off)
        padded = np.pad(truth, 2)
        best = {1: np.full(len(rows), np.inf), 2: np.full(len(rows), np.inf)}
        for dr in range(-2, 3):
            for dc in range(-2, 3):
                t = padded[rows + 2 + dr, cols + 2 + dc]
                e = np.where(t > 0, np.abs(ours[rows, cols] - t), np.inf)
                for r in (1, 2):
                    if max(abs(dr), abs(dc)) <= r:
                        best[r] = np.minimum(best[r], e)
        for r in (1, 2):
            self._add(f'near{r}', (best[r] <= 0.05).sum())

    def report(self):
        c = self.counts
        covered, off = max(c.get('covered', 0), 1), max(c.get('off', 0), 1)
        print(f"more than 5 cm off along the ray: {100 * c['off'] / covered:.1f} % of the "
              f"covered pixels: {100 * c['edge'] / covered:.1f} at depth edges of the truth, "
              f"{100 * c['grazing'] / covered:.1f} at grazing incidence, "
              f"{100 * (c['off'] - c['edge'] - c['grazing']) / covered:.1f} elsewhere")
        print(f"of those, with the true depth of a pixel at most 1 / 2 pixels away: "
              f"{100 * c['near1'] / off:.1f} / {100 * c['near2'] / off:.1f} %")
        print('| depth, m | share of the covered % | off by more than 5 cm % |')
        print('|---|---|---|')
        for b in range(len(self.bins) - 1):
            n = c.get(f'covered{b}', 0)
            if n:
                print(f'| {self.bins[b]:g}-{self.bins[b + 1]:g} | {100 * n / covered:.1f} | '
                      f"{100 * c[f'off{b}'] / n:.1f} |")


class LidarAlongRay:
    """Per depth range: the LIDAR points within 5 cm of the truth along the
    camera's ray, the frame's own scan's and the other frames' scans' (all
    placed with the true poses), and our covered pixels within 5 cm."""
    bins = [0, 5, 10, 20, np.inf]

    def __init__(self, calib, lidar_from_cam, dataset):
        # Only --lidar needs it (it imports scipy); the scripts' folder is on
        # the path already.
        from lidar_map_accuracy import read_ply_xyz  # noqa: E402
        self.read_ply_xyz = read_ply_xyz
        self.dataset = dataset
        self.K = calib['K']
        self.width, self.height = int(calib['width']), int(calib['height'])
        self.cam_from_lidar = np.linalg.inv(lidar_from_cam)
        self.scans_in_cam = {}
        # own n, own within, other n, other within, pixels, pixels within.
        self.counts = np.zeros((len(self.bins) - 1, 6))

    def scan_in_cam(self, name):
        if name not in self.scans_in_cam:
            points = self.read_ply_xyz(os.path.join(self.dataset, 'lidar', f'{name}.ply'))
            self.scans_in_cam[name] = (points @ self.cam_from_lidar[:3, :3].T +
                                       self.cam_from_lidar[:3, 3])
        return self.scans_in_cam[name]

    def along_ray(self, truth, points):
        """Per depth bin, the usable points and those within 5 cm."""
        fx, fy, cx, cy = self.K
        points = points[points[:, 2] > 0.1]
        x = points[:, 0] / points[:, 2] * fx + cx
        y = points[:, 1] / points[:, 2] * fy + cy
        col, row = np.floor(x).astype(int), np.floor(y).astype(int)
        inside = (col >= 0) & (col < self.width - 1) & (row >= 0) & (row < self.height - 1)
        x, y, col, row, z = x[inside], y[inside], col[inside], row[inside], points[inside, 2]
        corners = np.stack([truth[row, col], truth[row, col + 1],
                            truth[row + 1, col], truth[row + 1, col + 1]])
        a, b = x - col, y - row
        sampled = ((1 - b) * ((1 - a) * corners[0] + a * corners[1]) +
                   b * ((1 - a) * corners[2] + a * corners[3]))
        # Visible (not behind the true surface) and off any depth edge.
        usable = ((corners.min(0) > 0) & (corners.max(0) < 1.05 * corners.min(0)) &
                  (np.abs(z - sampled) < 0.5))
        counts = np.zeros((len(self.bins) - 1, 2))
        for k in range(len(self.bins) - 1):
            in_bin = usable & (sampled >= self.bins[k]) & (sampled < self.bins[k + 1])
            counts[k] = [in_bin.sum(), (in_bin & (np.abs(z - sampled) <= 0.05)).sum()]
        return counts

    def add(self, truth, ours, name, poses):
        self.counts[:, 0:2] += self.along_ray(truth, self.scan_in_cam(name))
        rotation, centre = poses[name]  # world_from_cam
        for other in poses:
            if other == name:
                continue
            r, c = poses[other]
            in_world = self.scan_in_cam(other) @ r.T + c
            self.counts[:, 2:4] += self.along_ray(truth, (in_world - centre) @ rotation)
        covered = (truth > 0) & (ours > 0)
        for k in range(len(self.bins) - 1):
            pixels = covered & (truth >= self.bins[k]) & (truth < self.bins[k + 1])
            self.counts[k, 4:6] += [pixels.sum(), (pixels & (np.abs(ours - truth) <= 0.05)).sum()]

    def report(self):
        print('| depth, m | own scan: points | within 5 cm along the ray % | other frames\' scans: '
              'points | within 5 cm % | our covered pixels within 5 cm % |')
        print('|---|---|---|---|---|---|')
        for k in range(len(self.bins) - 1):
            own, own_within, other, other_within, pixels, ours = self.counts[k]
            if own or other or pixels:
                print(f'| {self.bins[k]:g}-{self.bins[k + 1]:g} | {int(own)} | '
                      f'{100 * own_within / max(own, 1):.1f} | {int(other)} | '
                      f'{100 * other_within / max(other, 1):.1f} | '
                      f'{100 * ours / max(pixels, 1):.1f} |')


def local_grey_stddev(path, window=9):
    """Per pixel, the standard deviation of the grey values (in [0, 1]) over
    a window x window neighbourhood."""
    from PIL import Image  # noqa: E402 (only --by_texture needs it)
    from scipy.ndimage import uniform_filter  # noqa: E402
    grey = np.asarray(Image.open(path).convert('L'), dtype=float) / 255.0
    mean = uniform_filter(grey, window)
    mean_sq = uniform_filter(grey * grey, window)
    return np.sqrt(np.maximum(mean_sq - mean * mean, 0.0))


if __name__ == '__main__':
    main()
