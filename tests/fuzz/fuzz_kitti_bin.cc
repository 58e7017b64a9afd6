// KITTI Velodyne .bin scans (float32 x y z reflectance records).
#include "src/lidar/scan_io.h"
#include "tests/fuzz/fuzz_util.h"

using namespace colmap_lidar;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::InitFuzzTarget();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::WriteInput("input.bin", data, size);
  fuzz::ExpectNoCrash([&] { ReadLidarScan(path); });
  fuzz::ExpectNoCrash([&] { CountLidarScanPoints(path); });
  return 0;
}
