// Identifier types shared with COLMAP 3.8 (base/types.h): the same widths and
// the same "invalid" sentinels, so that ids read from a COLMAP database or
// model keep their meaning here.
#pragma once

#include <cstdint>
#include <limits>

#include <Eigen/Core>

namespace Eigen {
using Matrix3x4d = Matrix<double, 3, 4>;
using Matrix3x4f = Matrix<float, 3, 4>;
}  // namespace Eigen

namespace colmap_lidar {

using camera_t = uint32_t;
using image_t = uint32_t;
using point2D_t = uint32_t;
using point3D_t = uint64_t;
// Unique id of an unordered image pair, as COLMAP computes it (database.h).
using image_pair_t = uint64_t;
// Id of one of our 3D line tracks (lines3D files, ext_line_tracks table).
using line3D_t = uint64_t;

constexpr camera_t kInvalidCameraId = std::numeric_limits<camera_t>::max();
constexpr image_t kInvalidImageId = std::numeric_limits<image_t>::max();
constexpr point2D_t kInvalidPoint2DIdx = std::numeric_limits<point2D_t>::max();
constexpr point3D_t kInvalidPoint3DId = std::numeric_limits<point3D_t>::max();
constexpr line3D_t kInvalidLine3DId = std::numeric_limits<line3D_t>::max();

// COLMAP's upper bound on image ids; pair ids are a * kMaxNumImages + b.
constexpr uint64_t kMaxNumImages = 2147483647;

using Vector3ub = Eigen::Matrix<uint8_t, 3, 1>;

}  // namespace colmap_lidar
