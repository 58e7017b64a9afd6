// PCD scans (ascii, binary, binary_compressed): our header check, then PCL's
// reader, then our field decoding.
#include <pcl/console/print.h>

#include "src/lidar/scan_io.h"
#include "tests/fuzz/fuzz_util.h"

using namespace colmap_lidar;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::InitFuzzTarget();
  // PCL prints every complaint with fprintf(stderr): silence it.
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::WriteInput("input.pcd", data, size);
  fuzz::ExpectNoCrash([&] { ReadLidarScan(path); });
  fuzz::ExpectNoCrash([&] { CountLidarScanPoints(path); });
  return 0;
}
