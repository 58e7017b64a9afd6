// COLMAP sparse model binary files and our lines3D.bin. Every reader gets
// the same bytes (each rejects the others' files quickly); what one of them
// accepts is checked for consistency, which must not crash either.
#include "colmap_ext/model/model_io.h"
#include "tests/fuzz/fuzz_util.h"

using namespace colmap_lidar;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::InitFuzzTarget();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::WriteInput("model.bin", data, size);
  Reconstruction reconstruction;
  fuzz::ExpectNoCrash([&] { ReadCamerasBinary(path, &reconstruction); });
  fuzz::ExpectNoCrash([&] { ReadImagesBinary(path, &reconstruction); });
  fuzz::ExpectNoCrash([&] { ReadPoints3DBinary(path, &reconstruction); });
  fuzz::ExpectNoCrash([&] { ReadLines3DBinary(path, &reconstruction); });
  fuzz::ExpectNoCrash([&] { reconstruction.CheckConsistency(); });
  return 0;
}
