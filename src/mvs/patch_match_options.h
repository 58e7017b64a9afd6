// Options of the LIDAR-initialised PatchMatch stereo (paper section III-E,
// after Schoenberger et al. 2016 "Pixelwise View Selection for Unstructured
// Multi-View Stereo" and Li et al.'s LIDAR initialisation). One struct for
// the whole command; the engine files each read the fields they need.
#pragma once

#include <string>

namespace colmap_lidar {

struct LidarPatchMatchOptions {
  // "lidar": depths/normals from sparse features and the fused LIDAR cloud
  // (lidar_fused.ply), densified by Delaunay interpolation; "random": random
  // depths and normals (COLMAP's photogrammetry baseline).
  std::string init = "lidar";
  // Maps are computed at this larger side at most (pixels); <= 0: full size.
  int max_image_size = -1;
  // Source views per reference at most (also caps "__auto__, N"), [1, 64].
  int max_num_src_images = 5;
  // Source views must see the reference's median-depth point under at least
  // this triangulation angle, degrees, >= 0.
  double min_triangulation_angle_deg = 1.0;
  // Weight of a shared LIDAR voxel against a shared sparse point in the
  // source-view score, >= 0.
  double lidar_covisibility_weight = 0.1;

  // Propagation takes, per direction, the lowest-cost neighbour among those
  // 1, 3, 5 and 7 pixels away; far_propagation extends these strips to 15
  // pixels (no extra cost evaluations).
  bool far_propagation = false;
  // Photometric red-black iterations (propagation + random refinement), >= 1.
  int num_iterations = 5;
  // Run the geometric-consistency pass and write *.geometric.bin maps.
  bool geom_consistency = true;
  // Iterations of the geometric pass, >= 1.
  int num_geom_iterations = 2;
  // Weight of the forward-backward reprojection error (pixels) added to the
  // per-view cost in the geometric pass, >= 0 (COLMAP: 0.3).
  double geom_consistency_regularizer = 0.3;
  // Reprojection errors are clamped to this in the cost, pixels, > 0.
  double geom_consistency_max_cost = 3.0;

  // NCC window: radius in pixels and sampling step, >= 1.
  int window_radius = 4;
  int window_step = 2;
  // Bilateral weights: spatial sigma (pixels; <= 0: window_radius) and
  // colour sigma (grey values in [0, 1]), > 0.
  double sigma_spatial = -1.0;
  double sigma_color = 0.2;
  // The cost of a hypothesis is the mean of the best ceil(fraction * n)
  // per-view costs (occlusion robustness), (0, 1].
  double best_views_fraction = 0.5;
  // Count only the sources whose image contains the hypothesis's point (in
  // front of the camera): n above is their number (at least 1), and the
  // geometric filter asks min(filter_min_num_consistent, that number + the
  // LIDAR) agreeing views. A view that cannot see a point neither confirms
  // nor refutes it; counting it as a failed match drops every pixel outside
  // the overlap of several sources (the frames of a walk 2 m apart overlap
  // by 40-50 %). A source that sees something else in front of the point
  // still counts (its image contains the point), so occlusion is not
  // mistaken for invisibility.
  bool visible_sources_only = true;
  // The geometric term and filter read a source's depth at the exact
  // sub-pixel projection, from the plane (depth and normal) of the nearest
  // source pixel, instead of the nearest pixel's depth. On a surface seen
  // obliquely the depth changes by several per cent per pixel (ground 5 m
  // ahead of a camera 1.5 m up: 0.7 % per pixel; 1.3 % at 10 m), so the half
  // pixel of rounding alone exceeded the filter's 1 % and, through a 2 m
  // baseline, moved the reprojection by more than its pixel: correct near
  // ground and walls were dropped in a speckle. Not in the paper or COLMAP.
  bool source_plane_depth = true;

  // Soft LIDAR prior (init lidar only): cost += weight * min(|d - d_lidar| /
  // (d_lidar * tolerance), 1) at every pixel of the interpolated
  // LIDAR/feature initialisation; the cost filter also keeps pixels within
  // the tolerance of it. 0: off (pure photometric PatchMatch from the LIDAR
  // initialisation). Default 1: a hypothesis must lower 1 - NCC by more
  // than 1 to leave the LIDAR plane by more than the tolerance.
  double lidar_prior_weight = 1.0;
  double lidar_prior_tolerance = 0.02;
  // The prior (and the LIDAR's vote in the geometric filter) also holds the
  // pixels of an interpolation triangle across a depth edge, which take the
  // nearest vertex's plane: a guess of where the edge lies. Off: those
  // pixels start from the guess but the photometry alone decides (a tree's
  // leaves and the wall behind them, a window recess's lip).
  bool lidar_prior_across_depth_edges = false;

  // Initialisation: LIDAR samples are dropped unless their depth is at most
  // (1 + occlusion_relative_tolerance) x the mean depth of the samples within
  // occlusion_window_radius pixels (the paper's neighbourhood check).
  int occlusion_window_radius = 5;
  double occlusion_relative_tolerance = 0.05;
  // A LIDAR voxel's depth is carried along its plane (the fused cloud's
  // normal) from its sub-pixel projection to its pixel's centre, and a
  // pixel hit by several voxels takes the median depth of its front surface
  // instead of the nearest (the front surface: the voxels within
  // occlusion_relative_tolerance of the nearest, up to the first gap of 1 %
  // of depth between consecutive ones). Off: the nearest voxel's own depth
  // (Li et al.'s pixel-scale z-buffer). Far surfaces seen at grazing
  // incidence change depth by centimetres per pixel, and the nearest of
  // several noisy samples is biased towards the camera: on the bent street,
  // 58 % of the nearest samples at 10-20 m were within 5 cm of the true
  // depth, 77 % of the medians at the centres (5 % band, no gap test). Not
  // in the paper.
  bool lidar_samples_at_pixel_centres = true;
  // Where the view sees a surface at more than this angle from its normal
  // (grazing), the plane interpolated from the view's own LIDAR scan
  // replaces that of the fused cloud, degrees in [0, 90]; 90: off. The own
  // scan carries no pose error and measures along rays close to the
  // camera's, while the other scans' error across the surface grows by
  // 1 / cos(angle) along the camera's ray; but its rings are sparse, and
  // where the surface faces the camera the fused cloud's denser sampling
  // holds the detail between them (src/mvs/own_scan.h). Off by default: at
  // 70 deg the synthetic cells' maps gain 0.01 to 2.3 points within 5 cm,
  // but on KITTI the mesh then holds 77.2 instead of 81.1 % of the in-view
  // LIDAR within 0.1 m (why is not established; docs/benchmarks/matrix.md).
  // Not in the paper.
  double lidar_own_scan_min_incidence_deg = 90.0;
  // Delaunay interpolation: a triangle whose vertex depths differ by more
  // than this ratio takes each pixel from its nearest vertex's plane
  // instead (no smearing across depth edges), > 1.
  double interpolation_max_depth_ratio = 1.2;
  // A triangle of three LIDAR samples whose longest 3D edge, over its mean
  // depth, exceeds this factor times the median of that ratio over the
  // view's LIDAR triangles is left uninterpolated: it spans space the LIDAR
  // did not sample (sky between two wall tops, a gap between buildings), not
  // a surface. >= 0; 0 interpolates every triangle.
  double interpolation_max_edge_factor = 5.0;
  // Pixels the interpolation leaves empty (outside the samples' hull: a
  // wall above the LIDAR's vertical field, the ground below it) start from
  // the plane of the nearest interpolated pixel instead of a random plane
  // (ExtrapolateToEmptyPixels). Starting hypotheses only: they carry no
  // LIDAR prior. Not in the paper (Li et al. and COLMAP start them
  // randomly).
  bool init_extrapolate_planes = true;
  // Geometric maps: where no source view can see the LIDAR prior's point
  // (behind every source or outside its image: what the first frame of a
  // walk sees beside it, which the later frames have passed), the pixel
  // takes the LIDAR's plane after the geometric pass instead of the
  // search's (which moves it to any depth that some source sees, since
  // matching anything costs less than an unverifiable hypothesis); the
  // geometric filter confirms it by the LIDAR alone and keeps it out of
  // fusion (KeepLidarWhereUnseen). The photometric maps, which the other
  // views read, stay as they are. Not in the paper or COLMAP.
  bool keep_lidar_where_unseen = true;
  // LIDAR points nearer than this to the camera are ignored, metres.
  double min_depth = 0.1;

  // Geometric maps: the empty pixels of a textureless region (no texture
  // edge inside it; NCC cannot verify a depth there) whose measured pixels
  // fit one plane take that plane (src/mvs/textureless_fill.h): plain
  // plaster above the LIDAR's vertical field, joined without an edge to the
  // same plaster below it, which the LIDAR measures. A region with no
  // measured pixel (the sky) stays empty. Interpolated, not measured: the
  // filled pixels are kept out of fusion. Not in the paper or COLMAP.
  bool fill_textureless_regions = true;

  // Filtering: photometric cost above this (1 - NCC) makes a pixel invalid,
  // (0, 2].
  double filter_max_cost = 0.6;
  // Geometric maps keep a pixel seen consistently by at least this many
  // source views, >= 0.
  int filter_min_num_consistent = 2;
  // Consistency: reprojection error, pixels, and relative depth error.
  double filter_max_reproj_error = 1.0;
  double filter_max_relative_depth_error = 0.01;
  // The reprojection tolerance of a source view grows by the parallax that
  // filter_max_relative_depth_error of its depth causes in the reference
  // image (PatchCostComputer::DepthErrorParallax). A fixed pixel tolerance
  // is strictest for the views under the widest triangulation angles, whose
  // depths are the most precise: in a walk a correct depth 1 % off in a view
  // 2 m away moves the reprojection by 1-3 pixels of a 640x480 image, so
  // correct near ground and walls were dropped while the depth test alone
  // would have kept them. Not in the paper or COLMAP.
  bool filter_reproj_parallax = true;
  // Geometric maps, init lidar: a pixel whose depth is within
  // filter_max_relative_depth_error of the initialisation's interpolated
  // LIDAR (and sparse feature) depth counts as one more consistent view. The LIDAR measures the surface
  // independently of the images, so one source view plus the LIDAR confirm
  // a pixel as well as two source views do.
  bool filter_lidar_as_view = true;
  // ... within this relative depth error of the LIDAR depth, > 0.
  double filter_lidar_max_relative_depth_error = 0.01;

  // Threads; <= 0: all cores.
  int num_threads = -1;
  // Seed of the per-pixel random numbers (results do not depend on threads).
  int seed = 0;
  // Recompute maps that exist already (default: resume, skip them).
  bool overwrite = false;

  bool Check() const;
  bool RandomInit() const { return init == "random"; }
};

}  // namespace colmap_lidar
