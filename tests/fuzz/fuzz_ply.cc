// PLY of any layout (ASCII, binary of either endianness, any elements and
// properties): ReadPly, ReadPlyPoints, and the scan reader and counter on a
// .ply scan.
#include "colmap_ext/util/ply.h"
#include "src/lidar/scan_io.h"
#include "tests/fuzz/fuzz_util.h"

using namespace colmap_lidar;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::InitFuzzTarget();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::WriteInput("input.ply", data, size);
  fuzz::ExpectNoCrash([&] { ReadPly(path); });
  fuzz::ExpectNoCrash([&] { ReadPlyPoints(path); });
  fuzz::ExpectNoCrash([&] { ReadLidarScan(path); });
  fuzz::ExpectNoCrash([&] { CountLidarScanPoints(path); });
  return 0;
}
