// The KITTI raw calibration files. The input is calib_cam_to_cam.txt, a line
// "%%", then calib_velo_to_cam.txt; they sit in a date folder with one image
// and one scan so that LoadKittiRawRecording gets past the calibration.
#include <filesystem>

#include "src/dataset/kitti_raw.h"
#include "src/dataset/recording.h"
#include "tests/fuzz/fuzz_util.h"

using namespace colmap_lidar;

namespace {

std::string DateDir() { return fuzz::TempDir() + "/2011_09_26"; }

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::InitFuzzTarget();
  const std::string date_dir = DateDir();
  for (const char* dir : {"/image_00/data", "/image_02/data",
                          "/velodyne_points/data"}) {
    std::filesystem::create_directories(date_dir + dir);
  }
  // Only listed, never decoded, by LoadKittiRawRecording.
  fuzz::WriteInput("2011_09_26/image_00/data/0000000000.png", "");
  fuzz::WriteInput("2011_09_26/image_02/data/0000000000.png", "");
  fuzz::WriteInput("2011_09_26/velodyne_points/data/0000000000.bin",
                   std::string(16, '\1'));
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string cam_to_cam;
  std::string velo_to_cam;
  fuzz::SplitInput(data, size, "\n%%\n", &cam_to_cam, &velo_to_cam);
  fuzz::WriteInput("2011_09_26/calib_cam_to_cam.txt", cam_to_cam);
  fuzz::WriteInput("2011_09_26/calib_velo_to_cam.txt", velo_to_cam);
  // Camera 2 (colour, the default) has its own files; camera 0 reads the
  // same keys with index 00, where R_rect and P_rect share the index.
  fuzz::ExpectNoCrash([&] { LoadKittiRawRecording(DateDir(), 2); });
  fuzz::ExpectNoCrash([&] { LoadKittiRawRecording(DateDir(), 0); });
  fuzz::ExpectNoCrash([&] { LoadRecording(fuzz::TempDir(), "auto", 2); });
  return 0;
}
