#include "src/eval/pose_evaluator.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include <Eigen/Geometry>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/logging.h"
#include "src/eval/pose_alignment.h"

namespace colmap_lidar {
namespace {

// The file name without folders and extension: "cam0/000042.png" ->
// "000042".
std::string FileStem(const std::string& name) {
  return std::filesystem::path(name).stem().string();
}

double RotationAngleDeg(const Eigen::Quaterniond& a,
                        const Eigen::Quaterniond& b) {
  const Eigen::Quaterniond relative = a.conjugate() * b;
  // atan2 form: accurate for small angles, unlike acos(w).
  const double angle =
      2.0 * std::atan2(relative.vec().norm(), std::abs(relative.w()));
  return angle * 180.0 / M_PI;
}

}  // namespace

bool IsPoseAlignment(const std::string& alignment) {
  return alignment == "none" || alignment == "se3" || alignment == "sim3" ||
         alignment == "se3_axes" || alignment == "sim3_axes";
}

bool PoseEvaluationOptions::Check() const {
  bool ok = true;
  if (!IsPoseAlignment(alignment)) {
    LOG(ERROR) << "PoseEvaluation.alignment must be none, se3, sim3, "
                  "se3_axes or sim3_axes, got '"
               << alignment << "'";
    ok = false;
  }
  if (!(axes_weight >= 0.0) || !std::isfinite(axes_weight)) {
    LOG(ERROR) << "PoseEvaluation.axes_weight must be >= 0, got "
               << axes_weight;
    ok = false;
  }
  ok &= CheckThresholds(position_thresholds_m,
                        "PoseEvaluation.position_thresholds_m");
  ok &= CheckThresholds(rotation_thresholds_deg,
                        "PoseEvaluation.rotation_thresholds_deg");
  return ok;
}

PoseEvaluation EvaluatePoses(const Reconstruction& estimate,
                             const std::vector<FramePose>& ground_truth,
                             const PoseEvaluationOptions& options) {
  THROW_CHECK(options.Check(), "Invalid PoseEvaluation options");
  PoseEvaluation evaluation;
  evaluation.alignment = options.alignment;
  evaluation.num_ground_truth_frames = ground_truth.size();
  evaluation.num_model_images = estimate.images.size();

  std::map<std::string, size_t> frame_index;
  for (size_t i = 0; i < ground_truth.size(); ++i) {
    frame_index.emplace(ground_truth[i].frame, i);
  }

  // Matched (image index, frame index), in model order.
  std::vector<std::pair<size_t, size_t>> matches;
  std::vector<bool> frame_matched(ground_truth.size(), false);
  for (size_t i = 0; i < estimate.images.size(); ++i) {
    const std::string& name = estimate.images[i].name;
    auto it = frame_index.find(name);
    if (it == frame_index.end()) {
      it = frame_index.find(FileStem(name));
    }
    if (it == frame_index.end()) {
      ++evaluation.num_unmatched_images;
      continue;
    }
    THROW_CHECK(!frame_matched[it->second],
                "Ground-truth frame '" << it->first
                                       << "' matches two model images (the "
                                          "second is '"
                                       << name << "')");
    frame_matched[it->second] = true;
    matches.emplace_back(i, it->second);
  }
  for (size_t i = 0; i < ground_truth.size(); ++i) {
    if (!frame_matched[i]) {
      evaluation.missing_frames.push_back(ground_truth[i].frame);
    }
  }
  evaluation.num_matched = matches.size();
  evaluation.num_missing = evaluation.missing_frames.size();
  if (matches.empty()) {
    LOG(WARNING) << "No model image matches a ground-truth frame";
  }

  Eigen::Matrix3Xd centers_est(3, matches.size());
  Eigen::Matrix3Xd centers_gt(3, matches.size());
  for (size_t k = 0; k < matches.size(); ++k) {
    centers_est.col(k) = estimate.images[matches[k].first].ProjectionCenter();
    centers_gt.col(k) =
        ground_truth[matches[k].second].world_from_cam.translation;
    THROW_CHECK(centers_est.col(k).allFinite(),
                "Model image '" << estimate.images[matches[k].first].name
                                << "' has a non-finite pose");
  }

  if (options.alignment != "none") {
    THROW_CHECK(matches.size() >= 3,
                "PoseEvaluation.alignment=" << options.alignment << " needs "
                    << "at least 3 model images matched to ground-truth "
                    << "frames, got " << matches.size() << " ("
                    << estimate.images.size() << " model images, "
                    << ground_truth.size() << " ground-truth frames)");
    const Eigen::Vector3d mean_est = centers_est.rowwise().mean();
    const double spread =
        (centers_est.colwise() - mean_est).colwise().squaredNorm().sum();
    THROW_CHECK(spread > 0.0,
                "PoseEvaluation.alignment=" << options.alignment
                    << ": all matched model camera centres coincide");
    if (options.alignment == "se3" || options.alignment == "sim3") {
      const Eigen::Matrix4d transform =
          Eigen::umeyama(centers_est, centers_gt,
                         /*with_scaling=*/options.alignment == "sim3");
      evaluation.scale = options.alignment == "sim3"
                             ? transform.block<3, 1>(0, 0).norm()
                             : 1.0;
      evaluation.rotation = transform.block<3, 3>(0, 0) / evaluation.scale;
      evaluation.translation = transform.block<3, 1>(0, 3);
    } else {
      std::vector<Eigen::Vector3d> est(matches.size());
      std::vector<Eigen::Vector3d> gt(matches.size());
      std::vector<Eigen::Quaterniond> est_rotations(matches.size());
      std::vector<Eigen::Quaterniond> gt_rotations(matches.size());
      for (size_t k = 0; k < matches.size(); ++k) {
        est[k] = centers_est.col(k);
        gt[k] = centers_gt.col(k);
        est_rotations[k] = estimate.images[matches[k].first]
                               .cam_from_world.rotation.conjugate();
        gt_rotations[k] = ground_truth[matches[k].second].world_from_cam.rotation;
      }
      const TrajectoryAlignment alignment = AlignCentresAndAxes(
          est, est_rotations, gt, gt_rotations,
          /*with_scale=*/options.alignment == "sim3_axes",
          options.axes_weight);
      evaluation.scale = alignment.scale;
      evaluation.rotation = alignment.rotation;
      evaluation.translation = alignment.translation;
    }
  }

  const Eigen::Quaterniond alignment_rotation(evaluation.rotation);
  std::vector<double> position_errors;
  std::vector<double> rotation_errors;
  for (size_t k = 0; k < matches.size(); ++k) {
    const Image& image = estimate.images[matches[k].first];
    const FramePose& gt = ground_truth[matches[k].second];
    ImagePoseError error;
    error.image_name = image.name;
    error.frame = gt.frame;
    const Eigen::Vector3d aligned_center =
        evaluation.scale * evaluation.rotation * centers_est.col(k) +
        evaluation.translation;
    error.position_error_m = (aligned_center - centers_gt.col(k)).norm();
    const Eigen::Quaterniond world_from_cam_aligned =
        alignment_rotation * image.cam_from_world.rotation.conjugate();
    error.rotation_error_deg = RotationAngleDeg(
        world_from_cam_aligned.normalized(), gt.world_from_cam.rotation);
    position_errors.push_back(error.position_error_m);
    rotation_errors.push_back(error.rotation_error_deg);
    evaluation.errors.push_back(error);
  }
  evaluation.position_stats_m = ComputeErrorStats(position_errors);
  evaluation.rotation_stats_deg = ComputeErrorStats(rotation_errors);

  // Relative pose error per step, in ground-truth order.
  std::vector<int> match_of_frame(ground_truth.size(), -1);
  for (size_t k = 0; k < matches.size(); ++k) {
    match_of_frame[matches[k].second] = static_cast<int>(k);
  }
  std::vector<double> step_translation_errors;
  std::vector<double> step_rotation_errors;
  for (size_t i = 0; i + 1 < ground_truth.size(); ++i) {
    const int a = match_of_frame[i];
    const int b = match_of_frame[i + 1];
    if (a < 0 || b < 0) {
      continue;
    }
    const Eigen::Quaterniond gt_a = ground_truth[i].world_from_cam.rotation;
    const Eigen::Quaterniond gt_b = ground_truth[i + 1].world_from_cam.rotation;
    const Eigen::Quaterniond est_a =
        estimate.images[matches[a].first].cam_from_world.rotation.conjugate();
    const Eigen::Quaterniond est_b =
        estimate.images[matches[b].first].cam_from_world.rotation.conjugate();
    const Eigen::Vector3d gt_step =
        gt_a.conjugate() * (centers_gt.col(b) - centers_gt.col(a));
    const Eigen::Vector3d est_step =
        evaluation.scale *
        (est_a.conjugate() * (centers_est.col(b) - centers_est.col(a)));
    step_translation_errors.push_back((gt_step - est_step).norm());
    step_rotation_errors.push_back(
        RotationAngleDeg((gt_a.conjugate() * gt_b).normalized(),
                         (est_a.conjugate() * est_b).normalized()));
  }
  evaluation.step_translation_stats_m =
      ComputeErrorStats(step_translation_errors);
  evaluation.step_rotation_stats_deg = ComputeErrorStats(step_rotation_errors);

  const double num_frames = static_cast<double>(ground_truth.size());
  evaluation.position_thresholds_m = options.position_thresholds_m;
  evaluation.rotation_thresholds_deg = options.rotation_thresholds_deg;
  for (const double t : options.position_thresholds_m) {
    evaluation.position_recalls.push_back(
        ShareBelow(position_errors, t, {}, num_frames));
  }
  for (const double t : options.rotation_thresholds_deg) {
    evaluation.rotation_recalls.push_back(
        ShareBelow(rotation_errors, t, {}, num_frames));
  }
  if (options.position_thresholds_m.size() ==
      options.rotation_thresholds_deg.size()) {
    for (size_t j = 0; j < options.position_thresholds_m.size(); ++j) {
      size_t count = 0;
      for (const ImagePoseError& error : evaluation.errors) {
        count += error.position_error_m < options.position_thresholds_m[j] &&
                 error.rotation_error_deg < options.rotation_thresholds_deg[j];
      }
      evaluation.pose_recalls.push_back(
          num_frames > 0 ? count / num_frames : 0.0);
    }
  }
  LOG(INFO) << "Pose evaluation: " << evaluation.num_matched << " of "
            << evaluation.num_ground_truth_frames
            << " ground-truth frames matched, position RMSE "
            << evaluation.position_stats_m.rmse << " m";
  return evaluation;
}

std::string FormatPoseEvaluation(const PoseEvaluation& evaluation) {
  std::ostringstream out;
  char line[256];
  out << "Pose evaluation (alignment " << evaluation.alignment << ")\n";
  std::snprintf(line, sizeof(line),
                "  frames: %zu ground truth, %zu model images, %zu matched, "
                "%zu missing, %zu model images without ground truth\n",
                evaluation.num_ground_truth_frames,
                evaluation.num_model_images, evaluation.num_matched,
                evaluation.num_missing, evaluation.num_unmatched_images);
  out << line;
  std::snprintf(line, sizeof(line), "  alignment scale: %.9g\n",
                evaluation.scale);
  out << line;
  std::snprintf(line, sizeof(line), "  %-14s %12s %12s %12s %12s\n", "error",
                "mean", "median", "rmse", "max");
  out << line;
  const ErrorStats& p = evaluation.position_stats_m;
  const ErrorStats& r = evaluation.rotation_stats_deg;
  std::snprintf(line, sizeof(line), "  %-14s %12.6f %12.6f %12.6f %12.6f\n",
                "position [m]", p.mean, p.median, p.rmse, p.max);
  out << line;
  std::snprintf(line, sizeof(line), "  %-14s %12.6f %12.6f %12.6f %12.6f\n",
                "rotation [deg]", r.mean, r.median, r.rmse, r.max);
  out << line;
  const ErrorStats& st = evaluation.step_translation_stats_m;
  const ErrorStats& sr = evaluation.step_rotation_stats_deg;
  std::snprintf(line, sizeof(line),
                "  per step (%zu steps between consecutive frames):\n",
                st.count);
  out << line;
  std::snprintf(line, sizeof(line), "  %-14s %12.6f %12.6f %12.6f %12.6f\n",
                "step trans [m]", st.mean, st.median, st.rmse, st.max);
  out << line;
  std::snprintf(line, sizeof(line), "  %-14s %12.6f %12.6f %12.6f %12.6f\n",
                "step rot [deg]", sr.mean, sr.median, sr.rmse, sr.max);
  out << line;
  out << "  recall (share of ground-truth frames):\n";
  const size_t rows = std::max(evaluation.position_thresholds_m.size(),
                               evaluation.rotation_thresholds_deg.size());
  std::snprintf(line, sizeof(line), "  %12s %10s %12s %10s %10s\n",
                "position [m]", "recall", "rot. [deg]", "recall", "both");
  out << line;
  for (size_t k = 0; k < rows; ++k) {
    std::string position_cells(23, ' ');
    std::string rotation_cells(23, ' ');
    std::string both_cell(10, ' ');
    char cell[64];
    if (k < evaluation.position_thresholds_m.size()) {
      std::snprintf(cell, sizeof(cell), "%12g %10.4f",
                    evaluation.position_thresholds_m[k],
                    evaluation.position_recalls[k]);
      position_cells = cell;
    }
    if (k < evaluation.rotation_thresholds_deg.size()) {
      std::snprintf(cell, sizeof(cell), "%12g %10.4f",
                    evaluation.rotation_thresholds_deg[k],
                    evaluation.rotation_recalls[k]);
      rotation_cells = cell;
    }
    if (k < evaluation.pose_recalls.size()) {
      std::snprintf(cell, sizeof(cell), "%10.4f", evaluation.pose_recalls[k]);
      both_cell = cell;
    }
    out << "  " << position_cells << " " << rotation_cells << " " << both_cell
        << "\n";
  }
  return out.str();
}

namespace {

Json StatsToJson(const ErrorStats& stats) {
  Json json;
  json["count"] = stats.count;
  json["mean"] = stats.mean;
  json["median"] = stats.median;
  json["rmse"] = stats.rmse;
  json["max"] = stats.max;
  return json;
}

}  // namespace

void WritePoseEvaluationJson(const std::string& path,
                             const PoseEvaluation& evaluation) {
  Json json;
  json["evaluator"] = "pose";
  json["alignment"] = evaluation.alignment;
  Json transform;
  transform["scale"] = evaluation.scale;
  transform["rotation"] = MatrixRowsToJson(evaluation.rotation);
  transform["translation"] = VectorToJson(evaluation.translation);
  json["transform"] = std::move(transform);
  json["num_ground_truth_frames"] = evaluation.num_ground_truth_frames;
  json["num_model_images"] = evaluation.num_model_images;
  json["num_matched"] = evaluation.num_matched;
  json["num_missing"] = evaluation.num_missing;
  json["num_unmatched_images"] = evaluation.num_unmatched_images;
  json["position_error_m"] = StatsToJson(evaluation.position_stats_m);
  json["rotation_error_deg"] = StatsToJson(evaluation.rotation_stats_deg);
  json["step_translation_error_m"] =
      StatsToJson(evaluation.step_translation_stats_m);
  json["step_rotation_error_deg"] =
      StatsToJson(evaluation.step_rotation_stats_deg);
  json["position_thresholds_m"] = evaluation.position_thresholds_m;
  json["position_recalls"] = evaluation.position_recalls;
  json["rotation_thresholds_deg"] = evaluation.rotation_thresholds_deg;
  json["rotation_recalls"] = evaluation.rotation_recalls;
  json["pose_recalls"] = evaluation.pose_recalls;
  json["missing_frames"] = evaluation.missing_frames;
  Json images = Json::array();
  for (const ImagePoseError& error : evaluation.errors) {
    Json& image = images.emplace_back();
    image["image_name"] = error.image_name;
    image["frame"] = error.frame;
    image["position_error_m"] = error.position_error_m;
    image["rotation_error_deg"] = error.rotation_error_deg;
  }
  json["images"] = std::move(images);
  WriteJsonFile(path, json);
}

Eigen::Affine3d GroundTruthFromEstimate(const PoseEvaluation& evaluation) {
  Eigen::Affine3d transform = Eigen::Affine3d::Identity();
  transform.linear() = evaluation.scale * evaluation.rotation;
  transform.translation() = evaluation.translation;
  return transform;
}

}  // namespace colmap_lidar
