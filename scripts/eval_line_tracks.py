#!/usr/bin/env python3
"""Precision of line tracks against ground-truth edges (no dependencies).

Usage: eval_line_tracks.py TRACKS.json POSES_GT.txt CREASE_EDGES.txt

TRACKS.json is `colmap-lidar line_matcher --export_tracks_path` output (each
observation's 3D endpoints in its camera frame); POSES_GT.txt the dataset's
world_from_cam poses (TUM layout, frame name first); CREASE_EDGES.txt the
synthesizer's ground_truth/crease_edges.txt. Each observation is taken to the
world with the ground-truth pose and labelled with the nearest ground-truth
edge (mean endpoint-to-segment distance <= --max_distance, angle <=
--max_angle_deg); observations with no such edge are unlabelled. With
--segment_labels FILE ("image_name segment_idx edge_idx" lines, as
benchmarks/bench_line_matching_segments writes for its ground-truth
segments), each observation carries the edge it was made from instead: the
nearest-edge label cannot tell apart edges closer than the depth noise.
With --calibration CALIBRATION.yaml (the dataset's), each observation is
labelled in its image instead: the true edges are projected with the
frame's true pose (and the camera's distortion), and the label is the one
whose projection lies nearest to the observation's 2D segment (mean
distance of its endpoints <= --max_distance_px, direction within
--max_angle_deg), among the edges within --max_distance_3d_m of its 3D
endpoints (the LIDAR depth only rules out edges far in front of or behind
it). Parallel edges a few cm apart (a window frame's and its recess's
sides) are a pixel or more apart in the image up to 20-30 m, where the
observations' 3D endpoints are off by several cm along the ray.

Printed: tracks, mean observations per track, labelled share, and
- precision: share of tracks whose observations all carry one and the same
  edge label (an unlabelled observation makes the track impure);
- precision_labelled: the same over labelled observations only;
- precision_collinear: like precision_labelled, collinear edges (e.g. the
  tops of a row of windows) counting as one line;
- not vertical: share of tracks whose mean world direction is more than
  --vertical_angle_deg from the z axis (horizontal edges constrain roll and
  height; without --segment_labels only);
- impure tracks by cause: an observation without a label; labelled edges at
  most --near_edges_m apart (parallel edges a few cm apart, e.g. a window
  frame's and its recess's sides, which the nearest-edge label cannot tell
  apart at the observations' error); edges farther apart (a wrong match).
"""
import argparse
import json
import math
import os


def quat_to_matrix(qx, qy, qz, qw):
    n = math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
    x, y, z, w = qx / n, qy / n, qz / n, qw / n
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def read_poses(path):
    poses = {}
    for line in open(path):
        line = line.strip()
        if not line or line.startswith('#'):
            continue
        f = line.split()
        t = [float(v) for v in f[1:4]]
        poses[f[0]] = (quat_to_matrix(*[float(v) for v in f[4:8]]), t)
    return poses


def read_edges(path):
    edges = []
    for line in open(path):
        line = line.strip()
        if not line or line.startswith('#'):
            continue
        v = [float(x) for x in line.split()[:6]]
        edges.append((v[0:3], v[3:6]))
    return edges


def sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def norm(a):
    return math.sqrt(dot(a, a))


def point_segment_distance(p, a, b):
    ab = sub(b, a)
    length2 = dot(ab, ab)
    t = 0.0 if length2 == 0 else max(0.0, min(1.0, dot(sub(p, a), ab) / length2))
    return norm(sub(p, [a[i] + t * ab[i] for i in range(3)]))


def point_line_distance(p, a, direction):
    ap = sub(p, a)
    along = dot(ap, direction)
    return norm([ap[i] - along * direction[i] for i in range(3)])


def observation_in_world(obs, poses):
    """An observation's 3D endpoints placed with its frame's pose in
    `poses` (read_poses), and its unit direction."""
    frame = os.path.splitext(os.path.basename(obs['image_name']))[0]
    rotation, translation = poses[frame]
    world = []
    for key in ('start3D_in_cam', 'end3D_in_cam'):
        p = obs[key]
        world.append([sum(rotation[r][c] * p[c] for c in range(3)) +
                      translation[r] for r in range(3)])
    d = sub(world[1], world[0])
    n = norm(d)
    return world, ([x / n for x in d] if n > 0 else [1.0, 0.0, 0.0])


def read_camera(path):
    """(model, params) of the dataset's calibration.yaml (no yaml module)."""
    model, params, section = None, None, None
    for raw in open(path):
        line = raw.split('#')[0].rstrip()
        if not line.strip():
            continue
        if not line.startswith(' '):
            section = line.split(':')[0].strip()
            continue
        key, _, value = line.strip().partition(':')
        if section == 'camera' and key == 'model':
            model = value.strip()
        elif section == 'camera' and key == 'params':
            params = [float(v) for v in value.strip().strip('[]').split(',')]
    supported = ('SIMPLE_PINHOLE', 'PINHOLE', 'SIMPLE_RADIAL', 'RADIAL', 'OPENCV')
    if model not in supported or params is None:
        raise SystemExit('%s: camera model %s is not one of %s' %
                         (path, model, ', '.join(supported)))
    return model, params


def project(camera, p):
    """Pixel of the camera-frame point p (COLMAP's models), or None behind
    the camera."""
    model, k = camera
    if p[2] <= 1e-6:
        return None
    u, v = p[0] / p[2], p[1] / p[2]
    if model in ('SIMPLE_PINHOLE', 'SIMPLE_RADIAL', 'RADIAL'):
        fx = fy = k[0]
        cx, cy = k[1], k[2]
        extra = k[3:]
    else:
        fx, fy, cx, cy = k[0:4]
        extra = k[4:]
    if model in ('SIMPLE_RADIAL', 'RADIAL', 'OPENCV'):
        k1 = extra[0]
        k2 = extra[1] if model in ('RADIAL', 'OPENCV') else 0.0
        r2 = u * u + v * v
        radial = k1 * r2 + k2 * r2 * r2
        du, dv = u * radial, v * radial
        if model == 'OPENCV':
            p1, p2 = extra[2], extra[3]
            du += 2 * p1 * u * v + p2 * (r2 + 2 * u * u)
            dv += p1 * (r2 + 2 * v * v) + 2 * p2 * u * v
        u, v = u + du, v + dv
    return [fx * u + cx, fy * v + cy]


def point_polyline_2d(q, polyline):
    """Distance of q to a 2D polyline and the unit direction of its nearest
    piece."""
    best, best_direction = float('inf'), None
    for a, b in zip(polyline, polyline[1:]):
        ab = [b[0] - a[0], b[1] - a[1]]
        length2 = ab[0] * ab[0] + ab[1] * ab[1]
        if length2 == 0:
            continue
        t = max(0.0, min(1.0, ((q[0] - a[0]) * ab[0] + (q[1] - a[1]) * ab[1]) / length2))
        d = math.hypot(q[0] - a[0] - t * ab[0], q[1] - a[1] - t * ab[1])
        if d < best:
            n = math.sqrt(length2)
            best, best_direction = d, [ab[0] / n, ab[1] / n]
    return best, best_direction


def nearest_edge_in_image(obs, world, pose, camera, edges, max_distance_3d,
                          max_distance_px, cos_max):
    """Index of the true edge whose projection lies nearest to the
    observation's 2D segment (see the module comment), or None."""
    rotation, translation = pose  # world_from_cam
    s2, e2 = obs['start2D'], obs['end2D']
    length = math.hypot(e2[0] - s2[0], e2[1] - s2[1])
    if length == 0:
        return None
    direction = [(e2[0] - s2[0]) / length, (e2[1] - s2[1]) / length]
    best, best_distance = None, max_distance_px
    for e, (a, b) in enumerate(edges):
        if 0.5 * (point_segment_distance(world[0], a, b) +
                  point_segment_distance(world[1], a, b)) > max_distance_3d:
            continue
        polyline = []
        for i in range(17):
            t = i / 16.0
            w = [a[k] + t * (b[k] - a[k]) for k in range(3)]
            d = sub(w, translation)
            # cam = R^T (w - t)
            c = [sum(rotation[r][col] * d[r] for r in range(3)) for col in range(3)]
            pixel = project(camera, c)
            if pixel is not None:
                polyline.append(pixel)
        if len(polyline) < 2:
            continue
        d_start, dir_start = point_polyline_2d(s2, polyline)
        d_end, dir_end = point_polyline_2d(e2, polyline)
        distance = 0.5 * (d_start + d_end)
        if distance > best_distance:
            continue
        if max(abs(direction[0] * dir_start[0] + direction[1] * dir_start[1]),
               abs(direction[0] * dir_end[0] + direction[1] * dir_end[1])) < cos_max:
            continue
        best, best_distance = e, distance
    return best


def edge_directions(edges):
    directions = []
    for a, b in edges:
        d = sub(b, a)
        n = norm(d)
        directions.append([x / n for x in d] if n > 0 else [1.0, 0.0, 0.0])
    return directions


def collinear_groups(edges, directions):
    """find(edge index) -> its group: collinear edges (same direction within
    2 deg, on each other's line within 5 cm) share one."""
    group = list(range(len(edges)))

    def find(i):
        while group[i] != i:
            group[i] = group[group[i]]
            i = group[i]
        return i
    cos_collinear = math.cos(math.radians(2.0))
    for i in range(len(edges)):
        for j in range(i + 1, len(edges)):
            if abs(dot(directions[i], directions[j])) < cos_collinear:
                continue
            if (point_line_distance(edges[j][0], edges[i][0], directions[i]) < 0.05 and
                    point_line_distance(edges[j][1], edges[i][0], directions[i]) < 0.05):
                group[find(i)] = find(j)
    return find


def nearest_edge(world, direction, edges, directions, max_distance, cos_max):
    """Index of the edge nearest to the world segment `world` (mean endpoint
    to edge distance <= max_distance, angle within acos(cos_max)), or None."""
    best, best_distance = None, max_distance
    for e, (a, b) in enumerate(edges):
        if abs(dot(direction, directions[e])) < cos_max:
            continue
        distance = 0.5 * (point_segment_distance(world[0], a, b) +
                          point_segment_distance(world[1], a, b))
        if distance <= best_distance:
            best, best_distance = e, distance
    return best


def max_edge_separation(labels, edges):
    """Largest distance from the midpoint of one labelled edge to another
    labelled edge, metres."""
    separation = 0.0
    for i in labels:
        for j in labels:
            if i == j:
                continue
            a, b = edges[j]
            middle = [0.5 * (edges[i][0][k] + edges[i][1][k]) for k in range(3)]
            separation = max(separation, point_segment_distance(middle, a, b))
    return separation


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument('tracks')
    parser.add_argument('poses_gt')
    parser.add_argument('crease_edges')
    parser.add_argument('--max_distance', type=float, default=0.15)
    parser.add_argument('--max_angle_deg', type=float, default=10.0)
    parser.add_argument('--segment_labels', default=None)
    parser.add_argument('--vertical_angle_deg', type=float, default=20.0)
    parser.add_argument('--near_edges_m', type=float, default=0.15)
    parser.add_argument('--calibration', default=None,
                        help="the dataset's calibration.yaml: label each "
                             "observation in its image (see above)")
    parser.add_argument('--max_distance_px', type=float, default=2.0)
    parser.add_argument('--max_distance_3d_m', type=float, default=1.0)
    args = parser.parse_args()

    true_labels = None
    if args.segment_labels:
        true_labels = {}
        for line in open(args.segment_labels):
            if line.startswith('#') or not line.strip():
                continue
            name, segment_idx, edge_idx = line.split()
            true_labels[(name, int(segment_idx))] = int(edge_idx)

    poses = read_poses(args.poses_gt)
    camera = read_camera(args.calibration) if args.calibration else None
    edges = read_edges(args.crease_edges)
    directions = edge_directions(edges)
    find = collinear_groups(edges, directions)

    cos_max = math.cos(math.radians(args.max_angle_deg))
    tracks = json.load(open(args.tracks))['tracks']
    num_observations = 0
    num_labelled = 0
    pure = pure_labelled = pure_collinear = 0
    # A track is vertical when its mean world direction is within
    # --vertical_angle_deg of the z axis (the synthesizer's up).
    num_vertical = 0
    # Impure tracks by cause (see the module comment).
    impure_unlabelled = impure_near = impure_far = 0
    cos_vertical = math.cos(math.radians(args.vertical_angle_deg))
    for track in tracks:
        labels = []
        track_direction = [0.0, 0.0, 0.0]
        for obs in track['observations']:
            num_observations += 1
            if true_labels is not None:
                best = true_labels.get((obs['image_name'], obs['segment_idx']))
                labels.append(best)
                num_labelled += best is not None
                continue
            world, d = observation_in_world(obs, poses)
            sign = 1.0 if dot(d, track_direction) >= 0 else -1.0
            track_direction = [track_direction[i] + sign * d[i]
                               for i in range(3)]
            if camera is not None:
                frame = os.path.splitext(os.path.basename(obs['image_name']))[0]
                best = nearest_edge_in_image(obs, world, poses[frame], camera,
                                             edges, args.max_distance_3d_m,
                                             args.max_distance_px, cos_max)
            else:
                best = nearest_edge(world, d, edges, directions,
                                    args.max_distance, cos_max)
            labels.append(best)
            num_labelled += best is not None
        if true_labels is None and norm(track_direction) > 0:
            num_vertical += (abs(track_direction[2]) / norm(track_direction)
                             >= cos_vertical)
        known = [l for l in labels if l is not None]
        pure += len(set(labels)) == 1 and labels[0] is not None
        pure_labelled += len(set(known)) <= 1
        pure_collinear += len(set(find(l) for l in known)) <= 1
        if len(set(labels)) == 1 and labels[0] is not None:
            continue
        if len(set(known)) <= 1:
            impure_unlabelled += 1
        elif max_edge_separation(set(known), edges) <= args.near_edges_m:
            impure_near += 1
        else:
            impure_far += 1
    n = max(1, len(tracks))
    print('tracks %d, observations %d, mean track length %.2f, labelled %.1f%%%s' %
          (len(tracks), num_observations, num_observations / n,
           100.0 * num_labelled / max(1, num_observations),
           ' (true edges)' if true_labels is not None else
           ' (in the images)' if camera is not None else ''))
    print('precision %.2f%%, precision_labelled %.2f%%, precision_collinear %.2f%%' %
          (100.0 * pure / n, 100.0 * pure_labelled / n, 100.0 * pure_collinear / n))
    if true_labels is None:
        print('not vertical %.1f%% (direction more than %g deg from the z axis)' %
              (100.0 * (len(tracks) - num_vertical) / n, args.vertical_angle_deg))
    print('impure %d: %d with an unlabelled observation, %d joining edges at most '
          '%g m apart, %d joining edges farther apart' %
          (impure_unlabelled + impure_near + impure_far, impure_unlabelled,
           impure_near, args.near_edges_m, impure_far))


if __name__ == '__main__':
    main()
