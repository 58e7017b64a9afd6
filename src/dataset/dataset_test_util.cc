#include "src/dataset/dataset_test_util.h"

#include <cstdio>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"
#include "src/dataset/kitti_raw.h"
#include "src/dataset/poses.h"
#include "src/lidar/scan_io.h"

namespace colmap_lidar {
namespace testing {

void MakeRigDatasetFromKitti(const std::string& dataset_path, int num_frames) {
  const Recording kitti = LoadKittiRawRecording(KittiSampleDir(), 2);
  THROW_CHECK(num_frames <= static_cast<int>(kitti.frames.size()),
              "The KITTI sample has only " << kitti.frames.size() << " frames");
  CreateDirIfNotExists(JoinPaths(dataset_path, "images"));
  CreateDirIfNotExists(JoinPaths(dataset_path, "lidar"));
  WriteCalibration(JoinPaths(dataset_path, "calibration.yaml"),
                   kitti.calibration);
  std::vector<FramePose> poses;
  for (int i = 0; i < num_frames; ++i) {
    char name[16];
    std::snprintf(name, sizeof(name), "%06d", i);
    const RecordingFrame& frame = kitti.frames[i];
    StagedFiles copy;
    copy.Copy(frame.image_path,
              JoinPaths(dataset_path, std::string("images/") + name + ".png"));
    copy.Commit();
    WriteLidarScanPly(
        JoinPaths(dataset_path, std::string("lidar/") + name + ".ply"),
        ReadLidarScan(frame.scan_path));
    FramePose pose;
    pose.frame = name;
    pose.world_from_cam.translation = Eigen::Vector3d(0, 0, 0.15 * i);
    poses.push_back(pose);
  }
  WritePoses(JoinPaths(dataset_path, "poses_prior.txt"), poses);
}

}  // namespace testing
}  // namespace colmap_lidar
