#!/usr/bin/python3
"""The ablation of issue 21: what each extension of colmap-lidar buys.

Needs a finished round of the benchmark matrix with the defaults and, for
the paper preset's side, one with the paper preset (configs/paper.ini, the
method as published) on some of the same cells:

  bash scripts/bench_matrix.sh --work W/default
  bash scripts/bench_matrix.sh --work W/paper \\
    --run_options "--project_path $PWD/configs/paper.ini"

then re-runs, on copies of run 1 of each cell, the stage an extension lives
in and the stages after it:
  - from the default, each extension removed alone (in W/default);
  - from the paper preset, each extension added alone (in W/paper);
the SfM extensions with scripts/bench_resfm.sh (lidar_mapper on a copy of the
run's database: the same features and matches; poses), the meshing ones with
scripts/bench_remesh.sh --from mesh and the PatchMatch ones with
scripts/bench_remesh.sh --from patch_match (mesh and depth maps, on the run's
poses). An extension is a set of options of configs/paper.ini: removing it
sets them to the paper's values, adding it sets them to the defaults. The
paper's own line term (lambda_L) is removed from both presets.

Then prints two tables (markdown). Per cell, the default, the paper preset
and the stock mapper's model that the paper preset starts from: images, the
paper's Table I error (the stock mapper sim3-aligned to the priors, ours
unaligned), poses after sim3 of centres and axes, the relative pose error
per step, mesh F at 0.05 / 0.1 m (after the alignment of the cameras, no
ICP) on the LIDAR-covered reference and on the whole visible reference
(mesh_evaluator --MeshEvaluation.visible_model_path with the true poses),
without line samples and LIDAR-only Poisson, and wall time. Then per cell
and variant the poses, F and the variant's wall time, beside the preset's
own run.

Usage: scripts/bench_ablation.py --default_work DIR [--paper_work DIR]
         [--cells a,b] [--parts sfm,lines,mesh,dense,lidar_fusion]
         [--presets default,paper]
         [--overwrite] [--table_only]
A variant already measured on a cell is kept unless --overwrite.
COLMAP_LIDAR_BIN selects the binary (default build/colmap-lidar).
"""
import argparse
import configparser
import json
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PAPER_INI = os.path.join(ROOT, "configs", "paper.ini")

# name -> (part, options of automatic_reconstructor's sections). "sfm" runs
# through lidar_mapper, "lines" too after clearing the lines (extracted
# again), "mesh" from the mesh stage, "dense" from PatchMatch, "lidar_fusion"
# from the dense stage (the LIDAR fusion and what follows).
EXTENSIONS = [
    ("lidar_pose_graph", "sfm",
     ["LidarMapper.init_method", "LineBundleAdjustment.lidar_edge_weight"]),
    ("lidar_line_term", "sfm", ["LineBundleAdjustment.lambda_lidar"]),
    ("lidar_point_planes", "sfm", ["LineBundleAdjustment.lidar_point_weight"]),
    ("association", "sfm",
     ["LineMatching.min_overlap", "LineMatching.max_rival_score_ratio",
      "LineMatching.pose_uncertainty_scale",
      "LineMatching.refine_relative_poses"]),
    # One round is the default since the rounds did not pay on the worst
    # cell; only the undo by the priors is left of this extension.
    ("prior_guard", "sfm", ["LidarMapper.max_prior_outlier_ratio"]),
    ("pending_images", "sfm", ["LidarMapper.register_pending_images"]),
    ("guided_matching", "sfm", ["LidarMapper.guided_matching"]),
    # Line extraction runs inside lidar_mapper: "lines" re-runs it too.
    ("plane_lifting", "lines", ["LidarMapper.plane_lifting"]),
    ("line_validation", "mesh",
     ["DelaunayMeshing.validate_lines", "DelaunayMeshing.snap_to_creases"]),
    ("crease_snapping", "mesh", ["DelaunayMeshing.snap_to_creases"]),
    ("lidar_denoising", "mesh", ["DelaunayMeshing.lidar_denoise_radius_m"]),
    ("lidar_vertex_merging", "mesh",
     ["DelaunayMeshing.min_lidar_vertex_distance_m"]),
    ("line_sample_spacing", "mesh", ["DelaunayMeshing.line_sample_step_m"]),
    ("free_space_filter", "lidar_fusion", ["LidarFusion.free_space_filter"]),
    ("lidar_cost_term", "dense", ["LidarPatchMatch.lidar_prior_weight"]),
    ("lidar_as_view", "dense", ["LidarPatchMatch.filter_lidar_as_view"]),
    ("view_selection", "dense",
     ["LidarPatchMatch.lidar_covisibility_weight",
      "LidarPatchMatch.visible_sources_only"]),
    ("subpixel_consistency", "dense",
     ["LidarPatchMatch.source_plane_depth",
      "LidarPatchMatch.filter_reproj_parallax"]),
    ("init_extensions", "dense",
     ["LidarPatchMatch.init_extrapolate_planes",
      "LidarPatchMatch.interpolation_max_edge_factor"]),
    ("samples_at_pixel_centres", "dense",
     ["LidarPatchMatch.lidar_samples_at_pixel_centres"]),
    ("textureless_fill", "dense",
     ["LidarPatchMatch.fill_textureless_regions"]),
    ("lidar_where_unseen", "dense",
     ["LidarPatchMatch.keep_lidar_where_unseen"]),
]
# The paper's own line term, removed from both presets.
PAPER_LINE_TERM = ("no_paper_line_term", "sfm",
                   {"LineBundleAdjustment.lambda_L": "0"})
SFM_SECTIONS = ("LidarMapper", "LineMatching", "LineBundleAdjustment")
SFM_PARTS = ("sfm", "lines")
# The first stage bench_remesh re-runs for each of the other parts.
REMESH_FROM = {"mesh": "mesh", "dense": "patch_match", "lidar_fusion": "dense"}


def log(message):
    print(f"[bench_ablation {time.strftime('%H:%M:%S')}] {message}",
          flush=True)


def read_ini(text):
    """{"Section.key": value} of an INI text (top-level keys unqualified)."""
    parser = configparser.ConfigParser(interpolation=None,
                                       comment_prefixes=("#", ";"))
    parser.optionxform = str
    parser.read_string("[__top__]\n" + text)
    values = {}
    for section in parser.sections():
        for key, value in parser.items(section):
            values[key if section == "__top__" else f"{section}.{key}"] = value
    return values


def binary():
    return os.environ.get("COLMAP_LIDAR_BIN",
                          os.path.join(ROOT, "build", "colmap-lidar"))


def presets():
    """(defaults, paper): automatic_reconstructor's options in both."""
    defaults = subprocess.run(
        [binary(), "automatic_reconstructor", "--check_options"],
        check=True, capture_output=True, text=True).stdout
    with open(PAPER_INI) as stream:
        paper = stream.read()
    return read_ini(defaults), read_ini(paper)


def as_arguments(options):
    arguments = []
    for key, value in sorted(options.items()):
        arguments += [f"--{key}", value]
    return arguments


def variants(defaults, paper):
    """(work key, name, part, options given on top of the run's preset)."""
    out = []
    for name, part, keys in EXTENSIONS:
        for key in keys:
            if key not in defaults or key not in paper:
                sys.exit(f"bench_ablation: {key} is not an option of "
                         "automatic_reconstructor")
        out.append(("default", f"no_{name}", part,
                     {key: paper[key] for key in keys}))
        out.append(("paper", f"with_{name}", part,
                     {key: defaults[key] for key in keys}))
    name, part, options = PAPER_LINE_TERM
    out.append(("default", name, part, options))
    out.append(("paper", name, part, options))
    return out


def paper_sfm_options(defaults, paper):
    """The paper preset's lidar_mapper options that differ from the
    defaults (bench_resfm re-runs lidar_mapper, which takes no preset of
    automatic_reconstructor)."""
    return {key: value for key, value in paper.items()
            if key.split(".")[0] in SFM_SECTIONS and defaults.get(key) != value}


def run(command):
    log(" ".join(command))
    result = subprocess.run(command, cwd=ROOT)
    if result.returncode != 0:
        log(f"failed ({result.returncode}): {' '.join(command[:4])} ...")


def variant_done(work, cell, name, part):
    if part in SFM_PARTS:
        return os.path.exists(os.path.join(work, cell, "run1", "resfm", name,
                                           "poses_sim3_axes.json"))
    return os.path.exists(os.path.join(work, cell, "remesh", name, "ws",
                                       "eval", "mesh_ours.json"))


def run_variants(args, defaults, paper):
    works = {"default": args.default_work, "paper": args.paper_work}
    paper_sfm = paper_sfm_options(defaults, paper)
    for work_key, name, part, options in variants(defaults, paper):
        if part not in args.parts or work_key not in args.presets:
            continue
        # A variant already measured on a cell is kept (--overwrite redoes it).
        cells = args.cells.split(",") if args.cells else sorted(
            c for c in os.listdir(works[work_key])
            if os.path.isdir(os.path.join(works[work_key], c, "run1", "ws")))
        cells = [c for c in cells if args.overwrite or
                 not variant_done(works[work_key], c, name, part)]
        if not cells:
            continue
        cells = ["--cells", ",".join(cells)]
        if part in SFM_PARTS:
            base = paper_sfm if work_key == "paper" else {}
            relines = ["--relines"] if part == "lines" else []
            run(["bash", "scripts/bench_resfm.sh", "--work", works[work_key],
                 "--name", name] + relines + cells +
                ["--"] + as_arguments({**base, **options}))
        else:
            preset = (["--project_path", PAPER_INI]
                      if work_key == "paper" else [])
            run(["bash", "scripts/bench_remesh.sh", "--work", works[work_key],
                 "--name", name, "--from", REMESH_FROM[part]] + cells +
                ["--"] + preset + as_arguments(options))


def load(path):
    if not os.path.exists(path):
        return None
    with open(path) as stream:
        return json.load(stream)


def evaluate_poses(model, dataset, alignment, out):
    """pose_evaluator of `model` (cached in `out`, unless written by a
    build without the relative pose error); None when it fails."""
    cached = load(out)
    if cached is None or "step_translation_error_m" not in cached:
        if not os.path.isdir(model):
            return None
        result = subprocess.run(
            [binary(), "pose_evaluator", "--input_path", model,
             "--ground_truth_path", os.path.join(dataset, "poses_gt.txt"),
             "--PoseEvaluation.alignment", alignment, "--output_path", out],
            capture_output=True, text=True)
        if result.returncode != 0:
            return None
    return load(out)


def pose_cells(model, dataset, cache):
    """images, Table I (paper protocol), sim3 of centres + axes, steps."""
    axes = evaluate_poses(model, dataset, "sim3_axes",
                          os.path.join(cache, "poses_sim3_axes_steps.json"))
    if axes is None:
        return ["-"] * 3
    images = f"{axes['num_matched']} / {axes['num_ground_truth_frames']}"
    steps = (f"{1000 * axes['step_translation_error_m']['mean']:.1f} mm / "
             f"{axes['step_rotation_error_deg']['mean']:.3f} deg")
    sim3 = (f"{100 * axes['position_error_m']['mean']:.2f} cm / "
            f"{axes['rotation_error_deg']['mean']:.3f} deg")
    return [images, sim3, steps]


def table_one(model, dataset, align_to_priors):
    sys.path.insert(0, os.path.join(ROOT, "scripts", "baselines"))
    import baselines_table  # noqa: E402 (numpy, only for the table)
    error = baselines_table.paper_position_error(model, dataset,
                                                 align_to_priors)
    return "-" if error is None else f"{error:.3f} m"


def evaluate_visible(mesh, model, cell_dir, out):
    """F on the whole visible reference (occluded parts removed): the mesh
    aligned by its model's cameras (centres and axes, as the pipeline's
    evaluation), recall over the reference points the true cameras could
    see (cached in `out`)."""
    if not os.path.exists(out):
        if not (os.path.exists(mesh) and os.path.isdir(model)):
            return None
        dataset = os.path.join(cell_dir, "dataset")
        result = subprocess.run(
            [binary(), "mesh_evaluator", "--input_path", mesh,
             "--reference_path", os.path.join(dataset, "reference.ply"),
             "--alignment", "se3_axes", "--alignment_model_path", model,
             "--ground_truth_poses_path", os.path.join(dataset, "poses_gt.txt"),
             "--output_path", out,
             "--MeshEvaluation.visible_model_path",
             os.path.join(cell_dir, "gt", "workspace", "sparse", "prior"),
             "--MeshEvaluation.reference_surface_path",
             os.path.join(dataset, "ground_truth", "scene.ply")],
            capture_output=True, text=True)
        if result.returncode != 0:
            return None
    return load(out)


def mesh_text(mesh):
    if mesh is None:
        return "-"
    return f"{mesh['fscore'][1]:.3f} / {mesh['fscore'][2]:.3f}"


def stage_seconds(ws, first):
    record = load(os.path.join(ws, "pipeline", "stages.json"))
    if record is None:
        return None
    names = [s["stage"] for s in record["stages"]]
    if first not in names:
        return None
    return sum(s["wall_seconds"] for s in record["stages"][names.index(first):]
               if s["stage"] in ("sfm", "dense", "patch_match", "fusion", "mesh"))


def seconds_text(value):
    return "-" if value is None else f"{value:.0f}"


def has_run(work, cell):
    return work is not None and os.path.isdir(os.path.join(work, cell, "run1", "ws"))


def cells_of(args):
    """The default's cells; the paper preset's rows where it ran too."""
    cells = sorted(d for d in os.listdir(args.default_work)
                   if has_run(args.default_work, d))
    if args.cells:
        cells = [c for c in cells if c in args.cells.split(",")]
    return cells


def print_presets_table(args):
    """The paper preset, the default and the stock mapper's model (which
    the paper preset's SfM starts from) side by side, per cell."""
    print("| cell | method | images | Table I: position error, stock mapper "
          "sim3 to the priors, ours unaligned | position / rotation after sim3 "
          "(centres + axes) | per step: translation / rotation | mesh F@0.05 / "
          "0.1 | without line samples | LIDAR-only Poisson | F@0.05 / 0.1 on the "
          "whole visible reference: ours / LIDAR-only | wall s, sfm to mesh |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for cell in cells_of(args):
        dataset = os.path.join(args.default_work, cell, "dataset")
        rows = [("colmap-lidar default", args.default_work, "sparse/refined", False),
                ("paper preset", args.paper_work, "sparse/refined", False),
                ("stock COLMAP mapper (the paper preset's start)", args.paper_work,
                 "sparse/lidar_mapper/mapper/0", True)]
        for method, work, model, is_mapper in rows:
            if not has_run(work, cell):
                continue
            run1 = os.path.join(work, cell, "run1")
            ws = os.path.join(run1, "ws")
            cache = os.path.join(run1, "ablation", method.split()[0].replace("-", "_")
                                 + ("_mapper" if is_mapper else ""))
            os.makedirs(cache, exist_ok=True)
            images, sim3, steps = pose_cells(os.path.join(ws, model), dataset, cache)[:3]
            first = table_one(os.path.join(ws, model), dataset, is_mapper)
            if is_mapper:
                mesh = nolines = lidar = visible = wall = "-"
            else:
                cell_dir = os.path.join(work, cell)
                refined = os.path.join(ws, "sparse", "refined")
                visible = (
                    mesh_text(evaluate_visible(
                        os.path.join(ws, "dense", "meshed-delaunay.ply"), refined,
                        cell_dir, os.path.join(cache, "visible_ours.json"))) + " / " +
                    mesh_text(evaluate_visible(
                        os.path.join(ws, "eval", "mesh_lidar_poisson.ply"), refined,
                        cell_dir, os.path.join(cache, "visible_lidar.json"))))
                mesh = mesh_text(load(os.path.join(ws, "eval", "mesh_ours.json")))
                nolines = mesh_text(load(os.path.join(
                    run1, "matrix", "nolines_eval", "mesh_ours.json")))
                lidar = mesh_text(load(os.path.join(
                    ws, "eval", "mesh_lidar_poisson.json")))
                wall = seconds_text(stage_seconds(ws, "sfm"))
            print(f"| {cell} | {method} | {images} | {first} | {sim3} | {steps} "
                  f"| {mesh} | {nolines} | {lidar} | {visible} | {wall} |")


def print_ablation_table(args, defaults, paper):
    works = {"default": args.default_work, "paper": args.paper_work}
    print("| cell | preset | variant | position / rotation after sim3 | per "
          "step: translation / rotation | mesh F@0.05 / 0.1 | wall s of the "
          "re-run stages |")
    print("|---|---|---|---|---|---|---|")
    for cell in cells_of(args):
        dataset = os.path.join(args.default_work, cell, "dataset")
        for work_key in ("default", "paper"):
            if not has_run(works[work_key], cell):
                continue
            run1 = os.path.join(works[work_key], cell, "run1")
            ws = os.path.join(run1, "ws")
            cache = os.path.join(run1, "ablation", "run")
            os.makedirs(cache, exist_ok=True)
            _, sim3, steps = pose_cells(os.path.join(ws, "sparse/refined"),
                                        dataset, cache)[:3]
            print(f"| {cell} | {work_key} | (the preset's run) | {sim3} | {steps} | "
                  f"{mesh_text(load(os.path.join(ws, 'eval', 'mesh_ours.json')))} | "
                  f"{seconds_text(stage_seconds(ws, 'sfm'))} |")
            for key, name, part, _ in variants(defaults, paper):
                if key != work_key:
                    continue
                if part in SFM_PARTS:
                    out = os.path.join(run1, "resfm", name)
                    if not os.path.exists(os.path.join(out, "poses_sim3_axes.json")):
                        continue
                    _, sim3, steps = pose_cells(
                        os.path.join(out, "ws", "sparse", "refined"), dataset, out)[:3]
                    wall = None
                    if os.path.exists(os.path.join(out, "wall_seconds")):
                        with open(os.path.join(out, "wall_seconds")) as stream:
                            wall = float(stream.read())
                    print(f"| {cell} | {work_key} | {name} | {sim3} | {steps} | "
                          f"(sfm only) | {seconds_text(wall)} |")
                else:
                    out_ws = os.path.join(works[work_key], cell, "remesh", name, "ws")
                    mesh = load(os.path.join(out_ws, "eval", "mesh_ours.json"))
                    if mesh is None:
                        continue
                    first = REMESH_FROM[part]
                    print(f"| {cell} | {work_key} | {name} | (the run's) | (the run's) | "
                          f"{mesh_text(mesh)} | "
                          f"{seconds_text(stage_seconds(out_ws, first))} |")


def print_table(args, defaults, paper):
    print_presets_table(args)
    print()
    print_ablation_table(args, defaults, paper)


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--default_work", required=True)
    parser.add_argument("--paper_work", default=None,
                        help="the paper preset's matrix; without it, only "
                             "the default's side")
    parser.add_argument("--cells", default="")
    parser.add_argument("--parts", default="sfm,lines,mesh")
    parser.add_argument("--presets", default="default,paper",
                        help="which side to run: default (extensions removed), "
                             "paper (extensions added)")
    parser.add_argument("--overwrite", action="store_true",
                        help="re-run variants already measured")
    parser.add_argument("--table_only", action="store_true")
    args = parser.parse_args()
    args.parts = args.parts.split(",")
    args.presets = args.presets.split(",")
    for preset in args.presets:
        if preset not in ("default", "paper"):
            sys.exit(f"bench_ablation: --presets takes default, paper; got {preset}")
    parts = SFM_PARTS + tuple(REMESH_FROM)
    for part in args.parts:
        if part not in parts:
            sys.exit(f"bench_ablation: --parts takes {', '.join(parts)}; "
                     f"got {part}")
    if args.paper_work is None and "paper" in args.presets:
        if "--presets" in sys.argv:
            sys.exit("bench_ablation: --presets paper needs --paper_work")
        args.presets = ["default"]
    for work in (args.default_work, args.paper_work):
        if work is not None and not os.path.isdir(work):
            sys.exit(f"bench_ablation: {work} is not a matrix work folder")
    args.default_work = os.path.abspath(args.default_work)
    if args.paper_work is not None:
        args.paper_work = os.path.abspath(args.paper_work)
    defaults, paper = presets()
    if not args.table_only:
        run_variants(args, defaults, paper)
    print_table(args, defaults, paper)


if __name__ == "__main__":
    main()
