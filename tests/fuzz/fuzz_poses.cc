// poses_prior.txt / poses_gt.txt ("frame tx ty tz qx qy qz qw" lines).
#include "src/dataset/poses.h"
#include "tests/fuzz/fuzz_util.h"

using namespace colmap_lidar;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::InitFuzzTarget();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::WriteInput("poses.txt", data, size);
  fuzz::ExpectNoCrash([&] { ReadPoses(path); });
  return 0;
}
