// The KITTI raw layout (Geiger et al., IJRR 2013): calib_cam_to_cam.txt,
// calib_velo_to_cam.txt, image_0N/data/*.png, velodyne_points/data/*.bin.
#pragma once

#include <string>

#include "src/dataset/recording.h"

namespace colmap_lidar {

// `path` is the date folder (holding the calib_*.txt files), or a folder that
// holds exactly one such date folder. Images come from image_0N/data in the
// date folder or in its single *_sync drive folder.
//
// The rectified camera N is a PINHOLE camera with the focal lengths and
// principal point of P_rect_0N, its principal point moved by +0.5 px to
// COLMAP's pixel-centre convention. cam_from_lidar is
// [I | K^-1 P_rect_0N(:,3)] * R_rect_00 * T_velo_to_cam, the chain of the
// KITTI development kit. There are no poses: frames have no prior.
Recording LoadKittiRawRecording(const std::string& path, int camera_index);

// Finds the folder with calib_cam_to_cam.txt as described above; empty when
// there is none.
std::string FindKittiCalibrationFolder(const std::string& path);

}  // namespace colmap_lidar
