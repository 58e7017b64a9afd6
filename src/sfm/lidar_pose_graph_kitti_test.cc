// The LIDAR pose graph on real scans: the KITTI raw sample (20 frames, the
// car creeping forward about 3 m past moving traffic). Its two-step loops
// are biased against the consecutive chain (8 cm longer on average, loop
// closures with t = 8): the graph must see it, drop the loops it admitted
// by the consecutive edges' noise floor, and keep the consecutive steps.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <glog/logging.h>

#include "colmap_ext/util/testing.h"
#include "src/dataset/recording.h"
#include "src/lidar/scan_io.h"
#include "src/sfm/lidar_pose_graph.h"

namespace colmap_lidar {
namespace {

TEST(LidarPoseGraphKitti, BiasedSkipOneLoopsAreDroppedAndTheChainKept) {
  const Recording recording =
      LoadRecording(testing::KittiSampleDir(), "auto", 2);
  ASSERT_EQ(recording.frames.size(), 20u);
  std::vector<LidarScan> scans;
  scans.reserve(recording.frames.size());
  for (const RecordingFrame& frame : recording.frames) {
    scans.push_back(ReadLidarScan(frame.scan_path));
  }
  // Priors: no recording prior; a constant 0.15 m step along the LIDAR's x
  // (forward), as a rough odometry would give.
  const Rigid3d& cam_from_lidar = recording.calibration.cam_from_lidar;
  std::vector<LidarPoseGraphFrame> frames(recording.frames.size());
  for (size_t k = 0; k < frames.size(); ++k) {
    frames[k].name = recording.frames[k].name;
    frames[k].cam_from_lidar = cam_from_lidar;
    const Rigid3d world_from_lidar(Eigen::Quaterniond::Identity(),
                                   Eigen::Vector3d(0.15 * k, 0.0, 0.0));
    frames[k].prior_world_from_cam = world_from_lidar * cam_from_lidar.Inverse();
    frames[k].scan = &scans[k];
  }
  LidarPoseGraphOptions options;
  options.num_threads = 2;
  // Only the skip-one loops (the radius candidates are beside the point and
  // cost registrations).
  options.max_loop_candidates_per_frame = 0;
  const LidarPoseGraphResult result = SolveLidarPoseGraph(frames, options);
  LOG(INFO) << result.Format() << "\n" << result.FormatEdges();

  EXPECT_GT(result.num_dropped_relaxed_loops, 0);
  const LidarEdgeNoiseEstimate& with_loops = result.edge_noise_before_drop;
  EXPECT_TRUE(with_loops.biased[3]) << with_loops.Format();
  EXPECT_GT(with_loops.mean[3], 0.03);
  for (const LidarPoseGraphEdge& edge : result.edges) {
    if (edge.loop) {
      EXPECT_FALSE(edge.used && edge.relaxed_loop) << edge.i << "->" << edge.j;
    }
  }
  // The solved steps follow the consecutive registrations (within 3 cm):
  // the biased loops did not stretch the trajectory.
  double registered_length_m = 0.0;
  double solved_length_m = 0.0;
  for (const LidarPoseGraphEdge& edge : result.edges) {
    if (edge.loop || !edge.used) continue;
    const Rigid3d solved =
        (result.world_from_cam[edge.i] * cam_from_lidar).Inverse() *
        (result.world_from_cam[edge.j] * cam_from_lidar);
    EXPECT_LT((solved.translation -
               edge.registration.target_from_source.translation)
                  .norm(),
              0.03)
        << edge.i << "->" << edge.j;
    registered_length_m += edge.registration.target_from_source.translation.norm();
    solved_length_m += solved.translation.norm();
  }
  EXPECT_NEAR(solved_length_m / registered_length_m, 1.0, 0.03);
}

}  // namespace
}  // namespace colmap_lidar
