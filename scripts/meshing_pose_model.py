#!/usr/bin/python3
"""Writes the COLMAP TXT pose model that the meshing benchmark runs on.

The camera and the image ids come from a model written by `lidar_importer`
(`<workspace>/sparse/prior`, converted to TXT), so that the model matches the
workspace's database and `colmap point_triangulator` accepts it. The poses come
from one of:
  * a TUM-layout pose file (`frame tx ty tz qx qy qz qw`, world_from_cam, as
    the dataset's poses_gt.txt), where frame <f> is the image whose name
    without extension is <f>;
  * a COLMAP TXT model folder (images.txt, cam_from_world), matched by name.
Images of the workspace without a pose are dropped (with a warning on stderr);
the model has no 3D points.

Usage: meshing_pose_model.py PRIOR_TXT_DIR POSES OUTPUT_DIR
"""
import os
import sys

import numpy as np


def quat_to_rot(qw, qx, qy, qz):
    q = np.array([qw, qx, qy, qz], dtype=float)
    q /= np.linalg.norm(q)
    w, x, y, z = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def rot_to_quat(r):
    """Returns (qw, qx, qy, qz) with qw >= 0."""
    trace = np.trace(r)
    if trace > 0:
        s = 2.0 * np.sqrt(trace + 1.0)
        q = [0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s,
             (r[1, 0] - r[0, 1]) / s]
    else:
        i = int(np.argmax(np.diag(r)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * np.sqrt(1.0 + r[i, i] - r[j, j] - r[k, k])
        q = [0.0, 0.0, 0.0, 0.0]
        q[0] = (r[k, j] - r[j, k]) / s
        q[1 + i] = 0.25 * s
        q[1 + j] = (r[j, i] + r[i, j]) / s
        q[1 + k] = (r[k, i] + r[i, k]) / s
    q = np.array(q)
    return q if q[0] >= 0 else -q


def read_images_txt(path):
    """Returns [(image_id, (qw,qx,qy,qz,tx,ty,tz), camera_id, name)]."""
    images = []
    with open(path) as f:
        lines = [l for l in f if not l.startswith('#')]
    # Every image takes two lines: the pose line and the 2D point line.
    for pose_line in lines[0::2]:
        e = pose_line.split()
        if len(e) < 10:
            continue
        images.append((int(e[0]), tuple(float(v) for v in e[1:8]), int(e[8]),
                       e[9]))
    return images


def read_poses(path):
    """Returns {name without extension: (qw,qx,qy,qz,tx,ty,tz)} cam_from_world."""
    poses = {}
    if os.path.isdir(path):
        for _, pose, _, name in read_images_txt(os.path.join(path, 'images.txt')):
            poses[os.path.splitext(name)[0]] = pose
        return poses
    with open(path) as f:
        for line in f:
            e = line.split()
            if not e or e[0].startswith('#'):
                continue
            t_wc = np.array([float(v) for v in e[1:4]])
            qx, qy, qz, qw = (float(v) for v in e[4:8])
            r_wc = quat_to_rot(qw, qx, qy, qz)
            r_cw = r_wc.T
            t_cw = -r_cw @ t_wc
            poses[e[0]] = tuple(rot_to_quat(r_cw)) + tuple(t_cw)
    return poses


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    prior_dir, poses_path, out_dir = sys.argv[1:]
    poses = read_poses(poses_path)
    images = read_images_txt(os.path.join(prior_dir, 'images.txt'))
    os.makedirs(out_dir, exist_ok=True)
    kept = 0
    with open(os.path.join(out_dir, 'images.txt'), 'w') as f:
        for image_id, _, camera_id, name in images:
            pose = poses.get(os.path.splitext(name)[0])
            if pose is None:
                print(f'warning: no pose for {name} in {poses_path}; dropped',
                      file=sys.stderr)
                continue
            f.write(f'{image_id} ' + ' '.join(f'{v:.17g}' for v in pose) +
                    f' {camera_id} {name}\n\n')
            kept += 1
    with open(os.path.join(prior_dir, 'cameras.txt')) as src, \
            open(os.path.join(out_dir, 'cameras.txt'), 'w') as dst:
        dst.write(src.read())
    open(os.path.join(out_dir, 'points3D.txt'), 'w').close()
    print(f'{kept} of {len(images)} images posed from {poses_path}')
    if kept == 0:
        sys.exit('error: no image has a pose')


if __name__ == '__main__':
    main()
