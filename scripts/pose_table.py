#!/usr/bin/env python3
"""Markdown table of pose_evaluator JSON results, one row per method.

Usage: pose_table.py "label|result.json|time" ...
A missing JSON file gives a row saying the method failed.
"""
import json
import os
import sys


def row(label, path, time):
    if not os.path.exists(path):
        return f"| {label} | failed | | | | | | {time} |"
    with open(path) as f:
        r = json.load(f)
    p = r["position_error_m"]
    rot = r["rotation_error_deg"]
    recalls = dict(zip(r["position_thresholds_m"], r["position_recalls"]))
    rec5 = recalls.get(0.05, float("nan"))
    return (f"| {label} | {r['num_matched']}/{r['num_ground_truth_frames']} | "
            f"{p['mean']:.4f} | {p['median']:.4f} | {p['max']:.4f} | "
            f"{rot['mean']:.3f} | {rec5:.2f} | {time} |")


def main():
    print("| method | images | pos. mean [m] | pos. median [m] | pos. max [m] "
          "| rot. mean [deg] | recall @5 cm | time [s] |")
    print("|---|---|---|---|---|---|---|---|")
    for spec in sys.argv[1:]:
        label, path, time = spec.split("|")
        print(row(label, path, time))


if __name__ == "__main__":
    main()
