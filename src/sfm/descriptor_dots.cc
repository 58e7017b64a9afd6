#include "src/sfm/descriptor_dots.h"

#include <dlfcn.h>

#include <glog/logging.h>

#include "src/sfm/descriptor_dots_avx2.h"
#include "src/sfm/descriptor_dots_kernel.h"

namespace colmap_lidar {
namespace {

// The exported function's type (the library is loaded by name, not linked).
using DotsKernel = decltype(&ColmapLidarDescriptorDotsAvx2);

bool CpuHasAvx2Fma() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}

// The AVX2 kernel from its shared library, loaded on first use (a command
// that matches nothing never loads it): by the path CMake built it at, else
// by name through the loader's search path. nullptr, with one warning, when
// the CPU lacks AVX2 / FMA or the library cannot be loaded: the portable
// path gives the same products.
DotsKernel LoadAvx2Kernel() {
  if (!CpuHasAvx2Fma()) {
    return nullptr;
  }
  void* library = nullptr;
  for (const char* path : {COLMAP_LIDAR_DESCRIPTOR_DOTS_AVX2_PATH,
                           COLMAP_LIDAR_DESCRIPTOR_DOTS_AVX2_NAME}) {
    library = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (library != nullptr) break;
  }
  if (library == nullptr) {
    LOG(WARNING) << "descriptor dot products on the portable path: "
                 << dlerror();
    return nullptr;
  }
  const auto kernel = reinterpret_cast<DotsKernel>(
      dlsym(library, "ColmapLidarDescriptorDotsAvx2"));
  if (kernel == nullptr) {
    LOG(WARNING) << "descriptor dot products on the portable path: "
                 << dlerror();
  }
  return kernel;
}

DotsKernel Avx2Kernel() {
  static const DotsKernel kernel = LoadAvx2Kernel();
  return kernel;
}

}  // namespace

const char* DescriptorDotsPath() {
  return Avx2Kernel() != nullptr ? "avx2" : "portable";
}

void DescriptorDots(const float* rows1, const int num_rows, const float* cols2,
                    const int num_cols, const int dims, float* dots) {
  if (num_rows == 0 || num_cols == 0) return;
  if (const DotsKernel kernel = Avx2Kernel()) {
    kernel(rows1, num_rows, cols2, num_cols, dims, dots);
  } else {
    DescriptorDotsPortable(rows1, num_rows, cols2, num_cols, dims, dots);
  }
}

void DescriptorDotsPortable(const float* rows1, const int num_rows,
                            const float* cols2, const int num_cols,
                            const int dims, float* dots) {
  if (num_rows == 0 || num_cols == 0) return;
  descriptor_dots_internal::MultiplyDescriptors(rows1, num_rows, cols2,
                                                num_cols, dims, dots);
}

}  // namespace colmap_lidar
