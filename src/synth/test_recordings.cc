#include "src/synth/test_recordings.h"

namespace colmap_lidar {

SynthesisOptions QuickTestRecording(int num_frames, double path_fraction,
                                    int image_width, int image_height) {
  SynthesisOptions options;
  options.num_frames = num_frames;
  options.path_fraction = path_fraction;
  options.image_width = image_width;
  options.image_height = image_height;
  options.supersampling = 1;
  options.survey_num_stations = 0;
  options.write_depth_maps = false;
  options.num_threads = 2;
  return options;
}

}  // namespace colmap_lidar
