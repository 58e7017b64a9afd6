// Photometric and geometric matching costs of a plane hypothesis, as in
// COLMAP's PatchMatch (Schoenberger et al. 2016, section 4): the reference
// window around a pixel is warped into each source view by the homography
// of the hypothesised plane and compared with bilateral-weighted normalised
// cross-correlation; in the geometric pass the forward-backward reprojection
// error through the source view's depth map is added.
//
// Plane: the hypothesis (depth d, normal n) of reference pixel p defines the
// point X = d K_r^-1 p and the plane n . Y = n . X (reference camera frame).
// With src_from_ref = (R, t), a point Y on the plane maps to
// R Y + t (n . Y) / (n . X), hence the homography
//   H = K_s (R + t n^T / (n . X)) K_r^-1.
//
// Weighted NCC over window samples i with weights
//   w_i = exp(-|dp_i|^2 / (2 sigma_s^2) - (I_r(p_i) - I_r(p))^2 / (2 sigma_c^2)):
//   ncc = cov_w(r, s) / sqrt(var_w(r) var_w(s)), cost = 1 - ncc in [0, 2].
// A window leaving the source image, a plane seen edge-on or a textureless
// window (standard deviation < 0.005) costs kMaxCost.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "src/mvs/mvs_view.h"
#include "src/mvs/patch_match_options.h"
#include "src/mvs/plane_map.h"

namespace colmap_lidar {

constexpr float kMaxCost = 2.0f;

// The reference window of one pixel: sample offsets, grey values and
// bilateral weights, precomputed once per pixel for all hypotheses.
struct RefPatch {
  int row = 0;
  int col = 0;
  int num = 0;
  std::vector<float> dx, dy, value, weight;
  // Weighted mean and variance of the reference values; weights sum to 1.
  float mean = 0.0f;
  float variance = 0.0f;
};

class PatchCostComputer {
 public:
  // `ref` and `srcs` must outlive the computer.
  PatchCostComputer(const MvsView& ref, std::vector<const MvsView*> srcs,
                    const LidarPatchMatchOptions& options);

  // Source-view depth/normal maps for the geometric term (same order as the
  // sources; nullptr entries have no term). Maps must match the views' size.
  void SetSourceMaps(std::vector<const PlaneMap*> src_maps);
  bool HasSourceMaps() const { return !src_maps_.empty(); }

  int NumSources() const { return static_cast<int>(srcs_.size()); }
  const MvsView& Ref() const { return ref_; }

  void PrepareRefPatch(int row, int col, RefPatch* patch) const;
  // Whether pixel (row, col)'s window is too plain for NCC (its weighted
  // grey variance below the cost's floor): every hypothesis costs kMaxCost.
  bool Textureless(int row, int col) const;

  // 1 - weighted NCC for source `src`, in [0, kMaxCost].
  float PhotometricCost(const RefPatch& patch, int src, float depth,
                        const Eigen::Vector3f& normal) const;
  // Forward-backward reprojection error (pixels) of pixel (row, col) at
  // `depth` through source `src`'s depth map; infinity when the point leaves
  // the source image or hits an invalid source pixel. With
  // source_plane_depth the source's depth at the sub-pixel projection comes
  // from its nearest pixel's plane (so also in SourceDepthError).
  float ReprojectionError(int src, int row, int col, float depth) const;
  // Relative depth difference between the hypothesis seen from the source
  // and the source map at the projection; infinity as above.
  float SourceDepthError(int src, int row, int col, float depth) const;

  // Pixels by which the projection of pixel (row, col) at `depth` moves in
  // the reference image when its point moves along source `src`'s ray by
  // `relative` of its depth there: the reprojection error that a source depth
  // off by that much causes. 0 along the baseline, growing with the
  // triangulation angle; 0 for a point behind either camera.
  float DepthErrorParallax(int src, int row, int col, float depth,
                           float relative) const;

  // Whether the point of pixel (row, col) at `depth` lies in front of source
  // `src` and projects inside its image.
  bool SourceSees(int src, int row, int col, float depth) const;

  // The aggregated cost: per view photometric (+ regulariser * min(error,
  // max) when source maps are set), mean of the best
  // ceil(best_views_fraction * n) views; n is the number of sources, or with
  // visible_sources_only the number that see the point (at least 1).
  float Cost(const RefPatch& patch, float depth,
             const Eigen::Vector3f& normal) const;

 private:
  struct SourceGeometry {
    const MvsView* view = nullptr;
    // src_from_ref.
    Eigen::Matrix3f R;
    Eigen::Vector3f t;
    // K_s R K_r^-1 and K_s t.
    Eigen::Matrix3f A;
    Eigen::Vector3f b;
  };

  // Pixel (row, col) at `depth` seen from a source: its point in the
  // source's frame, its sub-pixel projection and the source map's depth
  // there (SourceDepthAt in ncc_cost.cc).
  struct SourceSurfacePoint {
    Eigen::Vector3f point_in_src;
    Eigen::Vector2f projection;
    float src_depth = 0.0f;
  };
  // nullopt without a source map, behind the source, outside its image or
  // on an invalid source pixel.
  std::optional<SourceSurfacePoint> SourceSurface(int src, int row, int col,
                                                  float depth) const;

  const MvsView& ref_;
  std::vector<SourceGeometry> srcs_;
  std::vector<const PlaneMap*> src_maps_;
  std::vector<float> offset_dx_, offset_dy_, spatial_weight_;
  float inv_two_sigma_color_sq_;
  int num_best_;
  float geom_regularizer_;
  float geom_max_cost_;
  double best_views_fraction_;
  bool visible_sources_only_;
  bool source_plane_depth_;
};

}  // namespace colmap_lidar
