// Ground-truth line segments for the line association benchmark
// (scripts/bench_line_matching.sh with SEGMENTS=gt): fills a workspace's
// ext_line_segments with the synthetic dataset's crease edges as each view
// sees them, so that the association (src/matching) can be measured on the
// real scene, poses and LIDAR visibility independently of the line
// extractor. Per view and edge: samples along the edge, projected with the
// ground-truth pose, visible where the ground-truth depth map agrees (3% +
// 5 cm); the longest visible run of at least 30 px becomes a segment with
// 0.5 px endpoint noise and 2 cm depth noise along the ray. Descriptors are
// zero (t_LBD has no effect): the geometry alone is measured.
//
// With LABELS_PATH, the edge each segment comes from is written there, one
// "image_name segment_idx edge_idx" per line (edge_idx: 0-based line of
// crease_edges.txt without comments), so that scripts/eval_line_tracks.py
// --segment_labels scores tracks by the true edge instead of the nearest
// one: with 2 cm depth noise, the nearest-edge label of an observation of
// one of two edges 2 cm apart is a coin toss.
//
// Usage: bench_line_matching_segments DATASET_DIR DATABASE_PATH [LABELS_PATH]
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <random>

#include "colmap_ext/database/database.h"
#include "colmap_ext/database/line_segments_table.h"
#include "colmap_ext/mvs/mat.h"
#include "colmap_ext/util/file.h"
#include "src/dataset/poses.h"
#include "src/eval/segment_io.h"

using namespace colmap_lidar;

int main(int argc, char** argv) {
  if (argc != 3 && argc != 4) {
    std::cerr << "Usage: " << argv[0]
              << " DATASET_DIR DATABASE_PATH [LABELS_PATH]\n";
    return 1;
  }
  std::ofstream labels;
  if (argc == 4) {
    labels.open(argv[3]);
    if (!labels) {
      std::cerr << "Cannot write " << argv[3] << "\n";
      return 1;
    }
    labels << "# image_name segment_idx edge_idx (crease_edges.txt order)\n";
  }
  const std::string dataset = argv[1];
  Database database(argv[2]);
  const std::vector<Segment3D> edges =
      ReadSegments(JoinPaths(dataset, "ground_truth/crease_edges.txt"));
  std::map<std::string, Rigid3d> cam_from_world;
  for (const FramePose& pose : ReadPoses(JoinPaths(dataset, "poses_gt.txt"))) {
    cam_from_world[pose.frame] = pose.world_from_cam.Inverse();
  }
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  size_t total = 0;
  const std::vector<DatabaseImage> images = database.ReadAllImages();
  for (const DatabaseImage& image : images) {
    const std::string frame = image.name.substr(0, image.name.rfind('.'));
    const Camera camera = *database.ReadCamera(image.camera_id);
    const Rigid3d& pose = cam_from_world.at(frame);
    const Mat<float> depth = ReadMat<float>(
        JoinPaths(dataset, "ground_truth/depth_maps/" + frame + ".bin"));
    std::vector<LineSegmentRecord> segments;
    for (size_t edge_idx = 0; edge_idx < edges.size(); ++edge_idx) {
      const Segment3D& edge = edges[edge_idx];
      const Eigen::Vector3d a = pose * edge.start;
      const Eigen::Vector3d b = pose * edge.end;
      const int num_samples =
          std::max(2, static_cast<int>(edge.Length() / 0.02));
      int best_first = -1, best_last = -1, first = -1;
      for (int k = 0; k <= num_samples; ++k) {
        const double t = static_cast<double>(k) / num_samples;
        const Eigen::Vector3d p = (1.0 - t) * a + t * b;
        bool visible = false;
        if (p.z() > 0.3) {
          const Eigen::Vector2d pixel = camera.ImgFromCam(p);
          const int col = static_cast<int>(std::floor(pixel.x()));
          const int row = static_cast<int>(std::floor(pixel.y()));
          if (col >= 1 && row >= 1 && col + 1 < static_cast<int>(camera.width) &&
              row + 1 < static_cast<int>(camera.height)) {
            // The nearest of the 3x3 depths: an edge sits on a discontinuity.
            double nearest = 1e9, farthest = 0.0;
            for (int dr = -1; dr <= 1; ++dr)
              for (int dc = -1; dc <= 1; ++dc) {
                const double d = depth.Get(row + dr, col + dc);
                if (d > 0) nearest = std::min(nearest, d);
                farthest = std::max(farthest, d);
              }
            visible = std::abs(p.z() - nearest) < 0.03 * p.z() + 0.05 ||
                      std::abs(p.z() - farthest) < 0.03 * p.z() + 0.05;
          }
        }
        if (visible) {
          if (first < 0) first = k;
          if (k - first > best_last - best_first) {
            best_first = first;
            best_last = k;
          }
        } else {
          first = -1;
        }
      }
      if (best_first < 0) continue;
      const Eigen::Vector3d p0 =
          a + (static_cast<double>(best_first) / num_samples) * (b - a);
      const Eigen::Vector3d p1 =
          a + (static_cast<double>(best_last) / num_samples) * (b - a);
      LineSegmentRecord record;
      record.start2D =
          camera.ImgFromCam(p0) + 0.5 * Eigen::Vector2d(normal(rng), normal(rng));
      record.end2D =
          camera.ImgFromCam(p1) + 0.5 * Eigen::Vector2d(normal(rng), normal(rng));
      if ((record.end2D - record.start2D).norm() < 30.0) continue;
      record.start3D_in_cam = p0 * (1.0 + 0.02 * normal(rng) / p0.norm());
      record.end3D_in_cam = p1 * (1.0 + 0.02 * normal(rng) / p1.norm());
      record.num_inliers = 10;
      if (labels.is_open()) {
        labels << image.name << ' ' << segments.size() << ' ' << edge_idx
               << '\n';
      }
      segments.push_back(record);
    }
    total += segments.size();
    WriteLineSegments(&database, image.image_id, segments);
  }
  std::cout << "Ground-truth segments: " << total << " in " << images.size()
            << " images" << std::endl;
  return 0;
}
