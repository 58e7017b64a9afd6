// poses_prior.txt / poses_gt.txt of the rig dataset format: TUM layout with
// the frame name in place of the timestamp, world_from_cam per line,
// "frame tx ty tz qx qy qz qw", '#' starts a comment.
#pragma once

#include <string>
#include <vector>

#include "colmap_ext/scene/rigid3.h"

namespace colmap_lidar {

struct FramePose {
  std::string frame;
  // Camera-to-world: the camera centre is world_from_cam.translation.
  Rigid3d world_from_cam;
};

// Throws colmap_lidar::Error naming the file and line on a wrong column
// count, a non-number, a non-finite value, a non-unit quaternion (norm off
// by more than 1e-3; accepted ones are renormalised) or a repeated frame.
std::vector<FramePose> ReadPoses(const std::string& path);
// Writes atomically with 17 significant digits; `comment` lines get '# '.
void WritePoses(const std::string& path, const std::vector<FramePose>& poses,
                const std::string& comment = "");

}  // namespace colmap_lidar
