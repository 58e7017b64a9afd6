// COLMAP sparse model text files and our lines3D.txt, as fuzz_model_bin.
#include "colmap_ext/model/model_io.h"
#include "tests/fuzz/fuzz_util.h"

using namespace colmap_lidar;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::InitFuzzTarget();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::WriteInput("model.txt", data, size);
  Reconstruction reconstruction;
  fuzz::ExpectNoCrash([&] { ReadCamerasText(path, &reconstruction); });
  fuzz::ExpectNoCrash([&] { ReadImagesText(path, &reconstruction); });
  fuzz::ExpectNoCrash([&] { ReadPoints3DText(path, &reconstruction); });
  fuzz::ExpectNoCrash([&] { ReadLines3DText(path, &reconstruction); });
  fuzz::ExpectNoCrash([&] { reconstruction.CheckConsistency(); });
  return 0;
}
