#include "src/sfm/descriptor_dots.h"

#include <Eigen/Core>

#include "src/sfm/descriptor_dots_avx2.h"

namespace colmap_lidar {
namespace {

bool CpuHasAvx2Fma() {
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  }();
  return has;
}

}  // namespace

const char* DescriptorDotsPath() {
  return CpuHasAvx2Fma() ? "avx2" : "portable";
}

void DescriptorDots(const float* rows1, const int num_rows, const float* cols2,
                    const int num_cols, const int dims, float* dots) {
  if (num_rows == 0 || num_cols == 0) return;
  if (CpuHasAvx2Fma()) {
    ColmapLidarDescriptorDotsAvx2(rows1, num_rows, cols2, num_cols, dims,
                                  dots);
  } else {
    DescriptorDotsPortable(rows1, num_rows, cols2, num_cols, dims, dots);
  }
}

void DescriptorDotsPortable(const float* rows1, const int num_rows,
                            const float* cols2, const int num_cols,
                            const int dims, float* dots) {
  if (num_rows == 0 || num_cols == 0) return;
  using RowMajor =
      Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Map<const RowMajor> a(rows1, num_rows, dims);
  const Eigen::Map<const Eigen::MatrixXf> b(cols2, dims, num_cols);
  Eigen::Map<RowMajor> result(dots, num_rows, num_cols);
  result.noalias() = a * b;
}

}  // namespace colmap_lidar
