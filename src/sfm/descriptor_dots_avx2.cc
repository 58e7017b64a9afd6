// Compiled with -mavx2 -mfma and hidden visibility into a shared library of
// its own (src/sfm/CMakeLists.txt), which descriptor_dots.cc loads only on a
// CPU with AVX2 and FMA: see descriptor_dots.h for why. Include nothing here
// that runs code at load time (no <iostream>).
#include "src/sfm/descriptor_dots_avx2.h"

#include "src/sfm/descriptor_dots_kernel.h"

extern "C" void ColmapLidarDescriptorDotsAvx2(const float* rows1,
                                              const int num_rows,
                                              const float* cols2,
                                              const int num_cols,
                                              const int dims, float* dots) {
  colmap_lidar::descriptor_dots_internal::MultiplyDescriptors(
      rows1, num_rows, cols2, num_cols, dims, dots);
}
