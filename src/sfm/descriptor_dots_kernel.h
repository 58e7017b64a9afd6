// The products of DescriptorDots (descriptor_dots.h), written once and
// compiled twice: into descriptor_dots.cc for the portable path and into
// descriptor_dots_avx2.cc (-mavx2 -mfma, a shared library of its own) for
// the AVX2 path. Internal linkage, so that each translation unit keeps the
// copy built for its own flags.
#pragma once

#include <Eigen/Core>

namespace colmap_lidar {
namespace descriptor_dots_internal {

// dots (row-major num_rows x num_cols) = rows1 (row-major num_rows x dims)
// * cols2 (column-major dims x num_cols).
static inline void MultiplyDescriptors(const float* rows1, const int num_rows,
                                       const float* cols2, const int num_cols,
                                       const int dims, float* dots) {
  using RowMajor =
      Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Map<const RowMajor> a(rows1, num_rows, dims);
  const Eigen::Map<const Eigen::MatrixXf> b(cols2, dims, num_cols);
  Eigen::Map<RowMajor> result(dots, num_rows, num_cols);
  result.noalias() = a * b;
}

}  // namespace descriptor_dots_internal
}  // namespace colmap_lidar
