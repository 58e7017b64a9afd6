// calibration.yaml of the rig dataset format.
#include "src/dataset/calibration.h"
#include "tests/fuzz/fuzz_util.h"

using namespace colmap_lidar;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::InitFuzzTarget();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::WriteInput("calibration.yaml", data, size);
  fuzz::ExpectNoCrash([&] { ReadCalibration(path); });
  return 0;
}
