// Test support: a room corner with six cameras around it, shared by the
// tests of the mesh evaluation job and of the documented JSON outputs.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace colmap_lidar {
namespace testing {

// A room corner: 6 x 6 m floor and two 3 m walls, each rectangle split into
// two triangles. Three orthogonal planes fix all six degrees of freedom (of
// an ICP); its creases run along the three axes.
struct Corner {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
};
Corner CornerMesh();

// Writes `points` (float64) and, if given, the triangles as faces.
void WritePointsPly(const std::string& path,
                    const std::vector<Eigen::Vector3d>& points,
                    const std::vector<Eigen::Vector3i>& triangles = {});

// The frame of a reconstruction: rotated by 20 deg about a tilted axis and
// shifted by (2, -1, 0.5) m from the reference's frame.
Eigen::Affine3d EstimateFromReference();

// A small residual misplacement: 1.5 deg and (8, -5, 6) cm.
Eigen::Affine3d Displacement();

// Ground-truth poses (poses_gt.txt layout) of six cameras around the corner
// and a binary sparse model of those cameras (100 x 80 PINHOLE) in the
// estimate's frame (EstimateFromReference).
void WriteCornerCameras(const std::string& ground_truth_poses_path,
                        const std::string& model_path);

}  // namespace testing
}  // namespace colmap_lidar
