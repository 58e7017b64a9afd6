#!/usr/bin/python3
"""Algorithm 1's LBD gate (t_LBD): the descriptors' Hamming distances on true
and false matches, and the threshold they give (issue 21).

For each cell of a finished benchmark matrix (scripts/bench_matrix.sh), the
line tracks that line_matcher made with the LBD gate off (t_LBD 256; the
matrix's run1/matrix/tracks_prior.json with the noisy priors and
tracks_refined.json with the refined poses) are labelled as
scripts/eval_line_tracks.py does (each observation placed with the true pose
and given its nearest ground-truth crease edge). Every pair of observations
of one track is a match that the geometric criteria accepted: true when both
carry the same edge (or collinear edges), false when both are labelled with
different ones. Their descriptors come from the run's ext_line_segments.

Printed per cell and pose source: the numbers of true and false matches,
quantiles of their distances, and for the threshold that keeps 99 % of the
true matches over all cells (the derived t_LBD), the share of false matches
it rejects; then, over all cells, what lower thresholds would reject of
each. A gate rejects a false match only if its distance lies above
the true matches' tail; where the two distributions overlap, the gate
cannot help.

Usage: scripts/lbd_gate_report.py --work DIR [--cells a,b]
"""
import argparse
import json
import math
import os
import sqlite3
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import eval_line_tracks as elt  # noqa: E402


def quantile(values, q):
    if not values:
        return float("nan")
    values = sorted(values)
    return values[min(len(values) - 1, int(math.floor(q * (len(values) - 1) + 0.5)))]


def descriptors(database):
    connection = sqlite3.connect(f"file:{database}?mode=ro", uri=True)
    rows = connection.execute(
        "SELECT image_id, idx, descriptor FROM ext_line_segments").fetchall()
    connection.close()
    return {(image_id, idx): int.from_bytes(blob, "little")
            for image_id, idx, blob in rows}


def edge_labeller(poses_gt, crease_edges, max_distance=0.15, max_angle_deg=10.0):
    """observation -> collinear group of its nearest true edge, or None (as
    eval_line_tracks.py labels them)."""
    poses = elt.read_poses(poses_gt)
    edges = elt.read_edges(crease_edges)
    directions = elt.edge_directions(edges)
    find = elt.collinear_groups(edges, directions)
    cos_max = math.cos(math.radians(max_angle_deg))

    def label(obs):
        world, d = elt.observation_in_world(obs, poses)
        best = elt.nearest_edge(world, d, edges, directions, max_distance, cos_max)
        return None if best is None else find(best)
    return label


def pair_distances(tracks_path, descriptor, label):
    true, false = [], []
    with open(tracks_path) as stream:
        tracks = json.load(stream)["tracks"]
    for track in tracks:
        observations = [(obs, label(obs)) for obs in track["observations"]]
        for i in range(len(observations)):
            for j in range(i + 1, len(observations)):
                (a, la), (b, lb) = observations[i], observations[j]
                if la is None or lb is None:
                    continue
                da = descriptor.get((a["image_id"], a["segment_idx"]))
                db = descriptor.get((b["image_id"], b["segment_idx"]))
                if da is None or db is None:
                    continue
                (true if la == lb else false).append(bin(da ^ db).count("1"))
    return true, false


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--work", required=True)
    parser.add_argument("--cells", default="")
    args = parser.parse_args()
    if not os.path.isdir(args.work):
        sys.exit(f"lbd_gate_report: {args.work} is not a matrix work folder")
    cells = sorted(c for c in os.listdir(args.work)
                   if os.path.exists(os.path.join(args.work, c, "run1", "matrix",
                                                  "tracks_refined.json")))
    if args.cells:
        cells = [c for c in cells if c in args.cells.split(",")]
    rows, all_true, all_false = [], [], []
    for cell in cells:
        run = os.path.join(args.work, cell, "run1")
        crease = os.path.join(args.work, cell, "dataset", "ground_truth",
                              "crease_edges.txt")
        poses_gt = os.path.join(args.work, cell, "dataset", "poses_gt.txt")
        if not (os.path.exists(crease) and os.path.exists(poses_gt)):
            continue
        descriptor = descriptors(os.path.join(run, "ws", "database.db"))
        label = edge_labeller(poses_gt, crease)
        for source in ("prior", "refined"):
            path = os.path.join(run, "matrix", f"tracks_{source}.json")
            if not os.path.exists(path):
                continue
            true, false = pair_distances(path, descriptor, label)
            rows.append((cell, source, true, false))
            all_true += true
            all_false += false
    if not rows:
        sys.exit("lbd_gate_report: no cell with tracks and ground truth")
    threshold = quantile(all_true, 0.99) + 1
    print(f"Derived t_LBD (keeps 99 % of the {len(all_true)} true matches of "
          f"all cells): {threshold} bits\n")
    print("| cell | poses | true matches | their distance p50 / p90 / p99 | "
          "false matches | their distance p10 / p50 / p90 | false rejected "
          f"at t_LBD {threshold} | true rejected |")
    print("|---|---|---|---|---|---|---|---|")
    for cell, source, true, false in rows + [("all", "both", all_true, all_false)]:
        rejected_false = sum(d >= threshold for d in false)
        rejected_true = sum(d >= threshold for d in true)
        print(f"| {cell} | {source} | {len(true)} | "
              f"{quantile(true, 0.5)} / {quantile(true, 0.9)} / {quantile(true, 0.99)} | "
              f"{len(false)} | "
              f"{quantile(false, 0.1)} / {quantile(false, 0.5)} / {quantile(false, 0.9)} | "
              f"{rejected_false} of {len(false)} | {rejected_true} of {len(true)} |")
    # What any lower gate would trade, over all cells.
    print("\n| t_LBD, bits | false matches rejected | true matches rejected |")
    print("|---|---|---|")
    for t in sorted({48, 64, 80, 96, 112, 128, threshold}):
        print(f"| {t} | {sum(d >= t for d in all_false)} of {len(all_false)} | "
              f"{sum(d >= t for d in all_true)} of {len(all_true)} |")


if __name__ == "__main__":
    main()
