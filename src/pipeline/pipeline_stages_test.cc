#include "src/pipeline/pipeline_stages.h"

#include <gtest/gtest.h>

namespace colmap_lidar {
namespace {

std::vector<std::string> Names(const std::vector<PipelineStage>& stages) {
  std::vector<std::string> names;
  for (const PipelineStage stage : stages) {
    names.push_back(PipelineStageName(stage));
  }
  return names;
}

TEST(PipelineStages, NamesAreUniqueAndParseBack) {
  const std::vector<PipelineStage> all = AllPipelineStages();
  ASSERT_EQ(all.size(), static_cast<size_t>(kNumPipelineStages));
  for (const PipelineStage stage : all) {
    std::vector<PipelineStage> parsed;
    ASSERT_TRUE(ParsePipelineStages(PipelineStageName(stage), &parsed));
    ASSERT_EQ(parsed.size(), 1u);
    EXPECT_EQ(parsed[0], stage);
  }
}

TEST(PipelineStages, ParsesRanges) {
  std::vector<PipelineStage> stages;
  ASSERT_TRUE(ParsePipelineStages("all", &stages));
  EXPECT_EQ(stages.size(), static_cast<size_t>(kNumPipelineStages));
  ASSERT_TRUE(ParsePipelineStages("dense:mesh", &stages));
  EXPECT_EQ(Names(stages), (std::vector<std::string>{
                               "dense", "patch_match", "fusion", "mesh"}));
  ASSERT_TRUE(ParsePipelineStages(":import", &stages));
  EXPECT_EQ(Names(stages),
            (std::vector<std::string>{"synthesize", "import"}));
  ASSERT_TRUE(ParsePipelineStages(" evaluate: ", &stages));
  EXPECT_EQ(Names(stages), (std::vector<std::string>{"evaluate", "report"}));
}

TEST(PipelineStages, RejectsUnknownNamesAndBackwardRanges) {
  std::vector<PipelineStage> stages = {PipelineStage::kMesh};
  EXPECT_FALSE(ParsePipelineStages("", &stages));
  EXPECT_FALSE(ParsePipelineStages("meshing", &stages));
  EXPECT_FALSE(ParsePipelineStages("mesh:dense", &stages));
  EXPECT_FALSE(ParsePipelineStages("sfm:nothing", &stages));
  // A failed parse leaves the output alone.
  EXPECT_EQ(stages.size(), 1u);
}

}  // namespace
}  // namespace colmap_lidar
