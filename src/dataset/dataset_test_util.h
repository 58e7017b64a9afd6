// Test fixtures: small real recordings in the rig format, made from the
// KITTI raw sample in ../shared (real images, real Velodyne scans).
#pragma once

#include <string>

namespace colmap_lidar {
namespace testing {

// Writes a rig-format dataset with the first `num_frames` KITTI frames
// (images copied, scans converted to binary PLY, calibration.yaml from the
// KITTI calibration, poses_prior.txt = the car moving 0.15 m per frame along
// the camera's optical axis, which is roughly its real motion). Frame names
// are 000000, 000001, ...
void MakeRigDatasetFromKitti(const std::string& dataset_path, int num_frames);

}  // namespace testing
}  // namespace colmap_lidar
