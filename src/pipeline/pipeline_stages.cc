#include "src/pipeline/pipeline_stages.h"

#include "colmap_ext/util/string.h"

namespace colmap_lidar {
namespace {

bool ParseStageName(const std::string& name, int default_index, int* index) {
  if (name.empty()) {
    *index = default_index;
    return true;
  }
  for (int i = 0; i < kNumPipelineStages; ++i) {
    if (name == PipelineStageName(static_cast<PipelineStage>(i))) {
      *index = i;
      return true;
    }
  }
  return false;
}

}  // namespace

const char* PipelineStageName(const PipelineStage stage) {
  switch (stage) {
    case PipelineStage::kSynthesize:
      return "synthesize";
    case PipelineStage::kImport:
      return "import";
    case PipelineStage::kOdometry:
      return "odometry";
    case PipelineStage::kSfm:
      return "sfm";
    case PipelineStage::kDense:
      return "dense";
    case PipelineStage::kPatchMatch:
      return "patch_match";
    case PipelineStage::kFusion:
      return "fusion";
    case PipelineStage::kMesh:
      return "mesh";
    case PipelineStage::kEvaluate:
      return "evaluate";
    case PipelineStage::kReport:
      return "report";
  }
  return "unknown";
}

std::vector<PipelineStage> AllPipelineStages() {
  std::vector<PipelineStage> stages;
  for (int i = 0; i < kNumPipelineStages; ++i) {
    stages.push_back(static_cast<PipelineStage>(i));
  }
  return stages;
}

bool ParsePipelineStages(const std::string& text,
                         std::vector<PipelineStage>* stages) {
  const std::string trimmed = StringTrim(text);
  int first = 0;
  int last = kNumPipelineStages - 1;
  if (trimmed != "all") {
    const size_t colon = trimmed.find(':');
    if (colon == std::string::npos) {
      if (trimmed.empty() || !ParseStageName(trimmed, 0, &first)) {
        return false;
      }
      last = first;
    } else if (!ParseStageName(StringTrim(trimmed.substr(0, colon)), 0,
                               &first) ||
               !ParseStageName(StringTrim(trimmed.substr(colon + 1)),
                               kNumPipelineStages - 1, &last) ||
               first > last) {
      return false;
    }
  }
  stages->clear();
  for (int i = first; i <= last; ++i) {
    stages->push_back(static_cast<PipelineStage>(i));
  }
  return true;
}

}  // namespace colmap_lidar
