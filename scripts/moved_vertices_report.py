#!/usr/bin/env python3
"""How far from the true surface the vertices that moved between two meshes
of the same triangulation lie, before and after.

Made for the crease snapping of the mesher (src/mesh/crease_snapping.h):
two runs of the mesh stage on the same inputs, one with
--DelaunayMeshing.snap_to_creases 0 and one with 1, give meshes whose
vertices are the same except those snapped onto a crease's faces; this
measures those vertices against the synthetic scene's true surface
(ground_truth/scene.ply), after carrying them into its frame with the
evaluation's alignment (eval/mesh_alignment.json, reference_from_estimate).

Usage: /usr/bin/python3 scripts/moved_vertices_report.py --before PLY
         --after PLY --alignment JSON --truth PLY [--max_vertices N]
  before, after  binary little-endian PLY meshes with the same vertex count
  alignment      the evaluate stage's eval/mesh_alignment.json
  truth          the true surface (a triangle mesh)
  max_vertices   moved vertices measured, an even sample (default 3000)
Prints one line: the moved vertices' distance to the true surface (median,
90th percentile, share within 2 and 5 cm) before and after, and the share
that ended more than 1 cm farther. Needs numpy (Debian's python3-numpy).
"""
import argparse
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from meshing_table import read_ply  # noqa: E402  (binary PLY: vertices, faces)


def distance_to_triangles(points, a, b, c, chunk=256):
    """Distance of each point to the nearest of the triangles (a, b, c):
    the closest point on a triangle by its Voronoi regions (Ericson,
    Real-Time Collision Detection, 5.1.5), brute force over the triangles."""
    best = np.full(len(points), np.inf)
    p = points[:, None, :]
    for s in range(0, len(a), chunk):
        ta, tb, tc = a[s:s + chunk], b[s:s + chunk], c[s:s + chunk]
        ab, ac = tb - ta, tc - ta
        ap, bp, cp = p - ta, p - tb, p - tc
        d1, d2 = (ab * ap).sum(-1), (ac * ap).sum(-1)
        d3, d4 = (ab * bp).sum(-1), (ac * bp).sum(-1)
        d5, d6 = (ab * cp).sum(-1), (ac * cp).sum(-1)
        va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
        safe = lambda x: np.where(np.abs(x) < 1e-300, 1e-300, x)
        denom = safe(va + vb + vc)
        q = ta + ab * (vb / denom)[..., None] + ac * (vc / denom)[..., None]
        # Later regions win: edges, then vertices.
        regions = [
            ((vb <= 0) & (d2 >= 0) & (d6 <= 0),
             ta + ac * (d2 / safe(d2 - d6))[..., None]),
            ((va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0),
             tb + (tc - tb) * ((d4 - d3) / safe((d4 - d3) + (d5 - d6)))[..., None]),
            ((vc <= 0) & (d1 >= 0) & (d3 <= 0),
             ta + ab * (d1 / safe(d1 - d3))[..., None]),
            ((d6 >= 0) & (d5 <= d6), np.broadcast_to(tc, q.shape)),
            ((d3 >= 0) & (d4 <= d3), np.broadcast_to(tb, q.shape)),
            ((d1 <= 0) & (d2 <= 0), np.broadcast_to(ta, q.shape)),
        ]
        for mask, value in regions:
            q = np.where(mask[..., None], value, q)
        best = np.minimum(best, np.linalg.norm(p - q, axis=-1).min(1))
    return best


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--before', required=True)
    parser.add_argument('--after', required=True)
    parser.add_argument('--alignment', required=True)
    parser.add_argument('--truth', required=True)
    parser.add_argument('--max_vertices', type=int, default=3000)
    args = parser.parse_args()
    if args.max_vertices < 1:
        sys.exit('--max_vertices must be >= 1')
    xyz = lambda v: np.stack([v['x'], v['y'], v['z']], 1).astype(np.float64)
    before = xyz(read_ply(args.before)[0])
    after = xyz(read_ply(args.after)[0])
    if before.shape != after.shape:
        sys.exit(f'{args.before} and {args.after} differ in vertex count: '
                 'not the same triangulation')
    with open(args.alignment) as f:
        transform = np.array(json.load(f)['reference_from_estimate'])
    truth_vertices, faces = read_ply(args.truth)
    truth = xyz(truth_vertices)
    if faces is None or len(faces) == 0:
        sys.exit(f'{args.truth}: no faces')
    moved = np.flatnonzero(np.linalg.norm(before - after, axis=1) > 0)
    if len(moved) == 0:
        print('no vertex moved')
        return
    sample = moved[np.linspace(0, len(moved) - 1,
                               min(len(moved), args.max_vertices)).astype(int)]
    to_truth = lambda x: x @ transform[:3, :3].T + transform[:3, 3]
    a, b, c = truth[faces[:, 0]], truth[faces[:, 1]], truth[faces[:, 2]]
    d0 = distance_to_triangles(to_truth(before[sample]), a, b, c)
    d1 = distance_to_triangles(to_truth(after[sample]), a, b, c)
    mm = lambda x: f'{1000 * x:.1f}'
    pct = lambda x: f'{100 * np.mean(x):.1f}'
    print(f'{len(moved)} vertices moved ({len(sample)} measured); distance to '
          f'the true surface: median {mm(np.median(d0))} -> '
          f'{mm(np.median(d1))} mm, 90th percentile '
          f'{mm(np.percentile(d0, 90))} -> {mm(np.percentile(d1, 90))} mm, '
          f'within 2 cm {pct(d0 < 0.02)} -> {pct(d1 < 0.02)} %, within 5 cm '
          f'{pct(d0 < 0.05)} -> {pct(d1 < 0.05)} %; more than 1 cm farther '
          f'after: {pct(d1 - d0 > 0.01)} %')


if __name__ == '__main__':
    main()
