// Small synthetic recordings for the tests of later stages: the options of
// a quick quad walk (no survey, no ground-truth depth maps, no
// supersampling, 2 threads), so that each test states only what it varies.
#pragma once

#include "src/synth/synthesis_options.h"

namespace colmap_lidar {

// `num_frames` frames over `path_fraction` of the default walk, at
// `image_width` x `image_height`; every other field is SynthesisOptions'
// default.
SynthesisOptions QuickTestRecording(int num_frames, double path_fraction,
                                    int image_width, int image_height);

}  // namespace colmap_lidar
