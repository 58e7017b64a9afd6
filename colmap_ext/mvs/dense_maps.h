// Depth and normal maps as COLMAP's patch_match_stereo writes them and
// stereo_fusion reads them (colmap-formats.md 4.1-4.4), over the planar Mat.
//
// Conventions shared by both maps:
// - Pixel (row, col) of a map is the image point (x = col, y = row) with NO
//   +0.5 offset (unlike the SfM models): the camera ray of that pixel is
//   K^-1 [col, row, 1], where K is the calibration at the map's resolution.
// - Depth is the camera-frame z coordinate, not the ray length; a value
//   <= 0 (or not finite) means "no depth".
// - Normals are unit vectors in the camera frame (x right, y down,
//   z forward) facing the camera (n . ray < 0); (0, 0, 0) means invalid.
#pragma once

#include <string>

#include <Eigen/Core>

#include "colmap_ext/mvs/mat.h"

namespace colmap_lidar {

// K^-1 [col, row, 1]: the ray of map pixel (row, col), with z = 1, so that
// depth * ray is the camera-frame point.
Eigen::Vector3d MvsPixelRay(const Eigen::Matrix3d& K, double row, double col);

// The calibration stereo_fusion uses for a map of map_width x map_height
// taken from an image of image_width x image_height: fx, cx scaled by
// map_width / image_width and fy, cy by map_height / image_height.
Eigen::Matrix3d ScaleCalibrationToMap(const Eigen::Matrix3d& K,
                                      size_t image_width, size_t image_height,
                                      size_t map_width, size_t map_height);

class DepthMap {
 public:
  DepthMap() = default;
  // All pixels invalid (0).
  DepthMap(size_t width, size_t height);
  // Throws unless the Mat has exactly one channel.
  explicit DepthMap(MatF mat);

  size_t GetWidth() const { return mat_.GetWidth(); }
  size_t GetHeight() const { return mat_.GetHeight(); }
  float Get(size_t row, size_t col) const { return mat_.Get(row, col, 0); }
  void Set(size_t row, size_t col, float depth) { mat_.Set(row, col, 0, depth); }
  bool IsValid(size_t row, size_t col) const;
  size_t NumValid() const;

  // The camera-frame point depth * K^-1 [col, row, 1]; K at the map's
  // resolution. Meaningless for invalid pixels.
  Eigen::Vector3d BackProject(size_t row, size_t col,
                              const Eigen::Matrix3d& K) const;

  const MatF& GetMat() const { return mat_; }

  // Throws naming the path on any Mat error or when the file has other than
  // one channel.
  static DepthMap Read(const std::string& path);
  // Atomic.
  void Write(const std::string& path) const;

 private:
  MatF mat_;
};

class NormalMap {
 public:
  NormalMap() = default;
  // All pixels invalid (0, 0, 0).
  NormalMap(size_t width, size_t height);
  // Throws unless the Mat has exactly three channels.
  explicit NormalMap(MatF mat);

  size_t GetWidth() const { return mat_.GetWidth(); }
  size_t GetHeight() const { return mat_.GetHeight(); }
  Eigen::Vector3f Get(size_t row, size_t col) const;
  void Set(size_t row, size_t col, const Eigen::Vector3f& normal);
  // True when the normal is not (0, 0, 0).
  bool IsValid(size_t row, size_t col) const;

  // `normal` flipped, if needed, so that normal . ray < 0 (facing the camera
  // along `ray`), as patch match and fusion expect.
  static Eigen::Vector3f OrientTowardsCamera(const Eigen::Vector3f& normal,
                                             const Eigen::Vector3f& ray);

  const MatF& GetMat() const { return mat_; }

  // Throws naming the path on any Mat error or when the file has other than
  // three channels.
  static NormalMap Read(const std::string& path);
  // Atomic; planar layout (all nx, then all ny, then all nz).
  void Write(const std::string& path) const;

 private:
  MatF mat_;
};

}  // namespace colmap_lidar
