#!/usr/bin/env python3
"""Completes the sfm_data.json that openMVG_main_SfMInit_ImageListing wrote
for a colmap-lidar recording (docs/dataset-format.md): the camera of
calibration.yaml (focal length, principal point and distortion, which the
listing leaves at zero), and optionally the prior camera centres of
poses_prior.txt as OpenMVG pose-centre priors (ViewPriors, the input of
`openMVG_main_SfM --prior_usage`), each axis weighted 1 / prior_sigma_m (the
adjustment's reprojection residuals are in pixels: a prior of sigma s metres
then weighs like a 1 px observation).

Usage: openmvg_sfm_data.py SFM_DATA_JSON DATASET [--priors] [--prior_sigma_m S]

Camera models: PINHOLE (fx = fy) and SIMPLE_PINHOLE -> pinhole,
SIMPLE_RADIAL -> pinhole_radial_k1, RADIAL -> pinhole_radial_k3 (k3 = 0),
OPENCV -> pinhole_brown_t2 (k3 = 0). Exits non-zero naming the file on a
missing or malformed input.
"""
import argparse
import json
import os
import re
import sys

# OpenMVG's polymorphic type of each camera model and its distortion field.
OPENMVG_MODELS = {
    "SIMPLE_PINHOLE": ("pinhole", None),
    "PINHOLE": ("pinhole", None),
    "SIMPLE_RADIAL": ("pinhole_radial_k1", "disto_k1"),
    "RADIAL": ("pinhole_radial_k3", "disto_k3"),
    "OPENCV": ("pinhole_brown_t2", "disto_t2"),
}


def fail(message):
    sys.exit("openmvg_sfm_data: " + message)


def read_camera(path):
    """model, width, height, params of calibration.yaml's camera block."""
    try:
        text = open(path).read()
    except OSError as error:
        fail(f"cannot read {path}: {error}")
    fields = {}
    in_camera = False
    for line in text.splitlines():
        if re.match(r"^camera:\s*$", line):
            in_camera = True
            continue
        if in_camera and not line.startswith(" "):
            break
        if in_camera and ":" in line:
            key, value = line.split(":", 1)
            fields[key.strip()] = value.split("#")[0].strip()
    try:
        model = fields["model"]
        width = int(fields["width"])
        height = int(fields["height"])
        params = [float(v) for v in fields["params"].strip("[]").split(",")]
    except (KeyError, ValueError) as error:
        fail(f"{path}: camera block incomplete or malformed ({error})")
    return model, width, height, params


def openmvg_intrinsic(model, params):
    """focal, principal point and distortion list in OpenMVG's order."""
    if model == "SIMPLE_PINHOLE":
        return params[0], params[1:3], []
    if model == "PINHOLE":
        fx, fy = params[0], params[1]
        if abs(fx - fy) > 1e-6 * fx:
            fail(f"PINHOLE with fx {fx} != fy {fy}: OpenMVG has one focal length")
        return fx, params[2:4], []
    if model == "SIMPLE_RADIAL":
        return params[0], params[1:3], [params[3]]
    if model == "RADIAL":
        return params[0], params[1:3], [params[3], params[4], 0.0]
    if model == "OPENCV":
        fx, fy = params[0], params[1]
        if abs(fx - fy) > 1e-6 * fx:
            fail(f"OPENCV with fx {fx} != fy {fy}: OpenMVG has one focal length")
        k1, k2, p1, p2 = params[4:8]
        return fx, params[2:4], [k1, k2, 0.0, p1, p2]
    fail(f"camera model {model} has no OpenMVG equivalent here "
         f"({', '.join(OPENMVG_MODELS)})")


def read_prior_centres(path):
    centres = {}
    try:
        lines = open(path).read().splitlines()
    except OSError as error:
        fail(f"cannot read {path}: {error}")
    for number, line in enumerate(lines, 1):
        if not line.strip() or line.startswith("#"):
            continue
        parts = line.split()
        try:
            values = [float(v) for v in parts[1:8]]
        except ValueError:
            values = []
        if len(values) != 7 or any(v != v or abs(v) == float("inf") for v in values):
            fail(f"{path}:{number}: expected 'frame tx ty tz qx qy qz qw' (finite)")
        centres[parts[0]] = values[0:3]  # world_from_cam translation = centre
    return centres


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("sfm_data")
    parser.add_argument("dataset")
    parser.add_argument("--priors", action="store_true")
    parser.add_argument("--prior_sigma_m", type=float, default=0.5)
    args = parser.parse_args()
    if not args.prior_sigma_m > 0:
        fail("--prior_sigma_m must be > 0")
    try:
        sfm_data = json.load(open(args.sfm_data))
    except (OSError, ValueError) as error:
        fail(f"cannot read {args.sfm_data}: {error}")

    model, width, height, params = read_camera(
        os.path.join(args.dataset, "calibration.yaml"))
    if model not in OPENMVG_MODELS:
        fail(f"camera model {model} has no OpenMVG equivalent here")
    type_name, disto_field = OPENMVG_MODELS[model]
    focal, principal_point, disto = openmvg_intrinsic(model, params)
    intrinsics = sfm_data.get("intrinsics", [])
    if len(intrinsics) != 1:
        fail(f"{args.sfm_data}: expected one shared intrinsic, found "
             f"{len(intrinsics)} (list the images with -g 1)")
    value = intrinsics[0]["value"]
    if value.get("polymorphic_name", type_name) != type_name:
        fail(f"{args.sfm_data}: intrinsic of type {value.get('polymorphic_name')},"
             f" expected {type_name} (camera model {model})")
    data = value["ptr_wrapper"]["data"]
    if data["width"] != width or data["height"] != height:
        fail(f"{args.sfm_data}: images of {data['width']}x{data['height']}, "
             f"calibration.yaml says {width}x{height}")
    data["focal_length"] = focal
    data["principal_point"] = list(principal_point)
    if disto_field is not None:
        data[disto_field] = disto

    if args.priors:
        centres = read_prior_centres(os.path.join(args.dataset, "poses_prior.txt"))
        weight = 1.0 / args.prior_sigma_m
        views = sfm_data["views"]
        # Cereal's polymorphic encoding: the first object of a registered
        # type carries its name and id 0x80000000 | n, later ones n; the
        # listing wrote plain views (0x40000000), so the intrinsic's type,
        # registered after the views, moves from n = 1 to n = 2.
        for index, view in enumerate(views):
            entry = view["value"]
            view_data = entry["ptr_wrapper"]["data"]
            frame = os.path.splitext(view_data["filename"])[0]
            if frame not in centres:
                fail(f"poses_prior.txt has no prior for image {view_data['filename']}")
            if index == 0:
                entry["polymorphic_id"] = 2147483649
                entry["polymorphic_name"] = "view_priors"
            else:
                entry["polymorphic_id"] = 1
                entry.pop("polymorphic_name", None)
            view_data["use_pose_center_prior"] = True
            view_data["center_weight"] = [weight, weight, weight]
            view_data["center"] = centres[frame]
        if value.get("polymorphic_id") == 2147483649:
            value["polymorphic_id"] = 2147483650
    json.dump(sfm_data, open(args.sfm_data, "w"), indent=4)
    print(f"openmvg_sfm_data: {args.sfm_data}: {type_name} f={focal}, "
          f"{len(sfm_data['views'])} views"
          + (f", centre priors of weight {1.0 / args.prior_sigma_m}" if args.priors else ""))


if __name__ == "__main__":
    main()
