// COLMAP's Mat files ("<w>&<h>&<d>&" + raw values): depth maps, normal maps,
// and the raw Mat of float and int32 (consistency maps).
#include "colmap_ext/mvs/dense_maps.h"
#include "colmap_ext/mvs/mat.h"
#include "tests/fuzz/fuzz_util.h"

using namespace colmap_lidar;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::InitFuzzTarget();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::WriteInput("map.bin", data, size);
  fuzz::ExpectNoCrash([&] { ReadMatHeader(path); });
  fuzz::ExpectNoCrash([&] { ReadMat<float>(path); });
  fuzz::ExpectNoCrash([&] { ReadMat<int32_t>(path); });
  fuzz::ExpectNoCrash([&] {
    const DepthMap depth_map = DepthMap::Read(path);
    // Touch every pixel through the accessors the pipeline uses.
    const Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
    volatile double sum = static_cast<double>(depth_map.NumValid());
    for (size_t row = 0; row < depth_map.GetHeight(); ++row) {
      for (size_t col = 0; col < depth_map.GetWidth(); ++col) {
        sum = sum + depth_map.BackProject(row, col, K).z();
      }
    }
  });
  fuzz::ExpectNoCrash([&] {
    const NormalMap normal_map = NormalMap::Read(path);
    size_t num_valid = 0;
    for (size_t row = 0; row < normal_map.GetHeight(); ++row) {
      for (size_t col = 0; col < normal_map.GetWidth(); ++col) {
        num_valid += normal_map.IsValid(row, col) ? 1 : 0;
      }
    }
    volatile size_t sink = num_valid;
    (void)sink;
  });
  return 0;
}
