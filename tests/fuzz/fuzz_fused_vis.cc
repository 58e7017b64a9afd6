// fused.ply.vis (uint64 count, then per point uint32 n and n image indices).
#include "colmap_ext/mvs/fused_vis.h"
#include "tests/fuzz/fuzz_util.h"

using namespace colmap_lidar;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::InitFuzzTarget();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::WriteInput("fused.ply.vis", data, size);
  fuzz::ExpectNoCrash([&] {
    const FusedVisibility visibility = ReadFusedVis(path);
    CheckFusedVisIndices(visibility, 8, path);
  });
  fuzz::ExpectNoCrash([&] { ReadFusedVis(path, 3); });
  return 0;
}
