#include "src/matching/relative_line_pose_problem.h"

#include "colmap_ext/scene/rigid3.h"
#include "src/matching/segment_similarity.h"

namespace colmap_lidar {
namespace relative_pose_internal {

Line MakeLine(const MatchingSegment& segment) {
  Line line;
  line.start = segment.start_in_cam;
  line.end = segment.end_in_cam;
  line.midpoint = 0.5 * (line.start + line.end);
  line.direction = (line.end - line.start).normalized();
  line.plane_normal = line.start.cross(line.end).normalized();
  return line;
}

LinePoseProblem MakeLinePoseProblem(const MatchingView& view1,
                                    const std::vector<int>& segments1,
                                    const MatchingView& view2) {
  LinePoseProblem problem;
  for (const int idx : segments1) {
    problem.lines1.push_back(MakeLine(view1.segments.at(idx)));
    problem.descriptors1.push_back(&view1.segments[idx].descriptor);
  }
  for (const MatchingSegment& segment : view2.segments) {
    problem.lines2.push_back(MakeLine(segment));
    problem.descriptors2.push_back(&segment.descriptor);
  }
  const Rigid3d prior = view2.cam_from_world * view1.cam_from_world.Inverse();
  problem.prior_rotation = prior.rotation.toRotationMatrix();
  problem.prior_translation = prior.translation;
  problem.focal_length2 = view2.camera.MeanFocalLength();
  problem.focal_length1 = view1.camera.MeanFocalLength();
  return problem;
}

void FindCandidates(const LineMatchingOptions& options,
                    LinePoseProblem* problem) {
  const std::vector<Line>& lines1 = problem->lines1;
  const std::vector<Line>& lines2 = problem->lines2;
  std::vector<Candidate>& candidates = problem->candidates;
  std::vector<std::vector<int>>& candidates_of = problem->candidates_of;
  candidates_of.assign(lines1.size(), {});
  for (size_t a = 0; a < lines1.size(); ++a) {
    const Line& line1 = lines1[a];
    const Eigen::Vector3d direction = problem->prior_rotation * line1.direction;
    const Eigen::Vector3d midpoint =
        problem->prior_rotation * line1.midpoint + problem->prior_translation;
    const MatchingThresholds gate =
        EffectiveThresholds(options, midpoint.z(), problem->focal_length2);
    for (size_t b = 0; b < lines2.size(); ++b) {
      const Line& line2 = lines2[b];
      if (AngleDeg(direction, line2.direction) >= gate.theta_deg) continue;
      const Eigen::Vector3d offset = midpoint - line2.midpoint;
      const double distance =
          (offset - offset.dot(line2.direction) * line2.direction).norm();
      if (distance >= gate.dO_m) continue;
      if (HammingDistance(*problem->descriptors1[a],
                          *problem->descriptors2[b]) >= gate.LBD) {
        continue;
      }
      Candidate candidate;
      candidate.a = static_cast<int>(a);
      candidate.b = static_cast<int>(b);
      candidate.direction_b = direction.dot(line2.direction) >= 0.0
                                  ? line2.direction
                                  : Eigen::Vector3d(-line2.direction);
      candidates_of[a].push_back(static_cast<int>(candidates.size()));
      candidates.push_back(candidate);
    }
  }
}

}  // namespace relative_pose_internal
}  // namespace colmap_lidar
