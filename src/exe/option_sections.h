// Option sections shared by several subcommands: each registers one options
// struct as "Section.name" options (see option_manager.h) plus its Check().
// A command that runs a stage alone and automatic_reconstructor, which runs
// it as part of the pipeline, register the same section, so that
// `--Synthesis.num_frames 20` means the same to both.
#pragma once

#include <string>

#include "src/dataset/importer.h"
#include "src/exe/option_manager.h"
#include "src/lidar/lidar_fusion.h"
#include "src/mesh/delaunay_mesher.h"
#include "src/mvs/patch_match_options.h"
#include "src/optim/line_bundle_adjustment.h"
#include "src/sfm/lidar_mapper.h"
#include "src/synth/synthesis_options.h"

namespace colmap_lidar {

// [Synthesis] (synth_commands.cc).
void AddSynthesisOptions(SynthesisOptions* synth, OptionManager* options);

// [LidarImport] (dataset_commands.cc).
void AddImporterOptions(ImporterOptions* importer, OptionManager* options);

// [LidarMapper] with its matching options (sfm_commands.cc).
void AddLidarMapperOptions(LidarMapperOptions* o, OptionManager* options);

// [LineBundleAdjustment]'s enums, read as names; the caller keeps this alive
// as long as the OptionManager.
struct LineBundleAdjustmentNames {
  std::string point_loss_type;
  std::string line_loss_type;
  std::string lidar_loss_type;
  std::string gauge;
};

// [LineBundleAdjustment] (sfm_commands.cc); the gauge and the pose priors
// only for line_bundle_adjuster (lidar_mapper sets them from its own).
void AddLineBundleAdjustmentOptions(LineBundleAdjustmentOptions* o,
                                    LineBundleAdjustmentNames* n,
                                    bool with_gauge_and_priors,
                                    OptionManager* options);

// [LidarFusion] (mvs_commands.cc).
void AddLidarFusionOptions(LidarFusionOptions* o, OptionManager* options);

// [LidarPatchMatch] (mvs_commands.cc).
void AddLidarPatchMatchOptions(LidarPatchMatchOptions* o,
                               OptionManager* options);

// [DelaunayMeshing]: the mesher's and its input's options
// (mesh_commands.cc).
void AddDelaunayMeshingOptions(DelaunayMeshingOptions* meshing,
                               MeshingInputOptions* input,
                               OptionManager* options);

}  // namespace colmap_lidar
