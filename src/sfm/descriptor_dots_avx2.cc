// Compiled with -mavx2 -mfma and hidden visibility into a shared library of
// its own (src/sfm/CMakeLists.txt), which descriptor_dots.cc loads only on a
// CPU with AVX2 and FMA: see descriptor_dots.h for why. Include nothing here
// that runs code at load time (no <iostream>).
#include "src/sfm/descriptor_dots_avx2.h"

#include <Eigen/Core>

extern "C" void ColmapLidarDescriptorDotsAvx2(const float* rows1,
                                              const int num_rows,
                                              const float* cols2,
                                              const int num_cols,
                                              const int dims, float* dots) {
  using RowMajor =
      Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Map<const RowMajor> a(rows1, num_rows, dims);
  const Eigen::Map<const Eigen::MatrixXf> b(cols2, dims, num_cols);
  Eigen::Map<RowMajor> result(dots, num_rows, num_cols);
  result.noalias() = a * b;
}
