#include "src/matching/pairwise_matcher.h"

#include <gtest/gtest.h>

#include "src/matching/synthetic_line_views.h"

namespace colmap_lidar {
namespace {

double ShareCorrect(const SyntheticLineScene& scene,
                    const std::vector<PairwiseLineMatch>& matches) {
  size_t correct = 0;
  for (const PairwiseLineMatch& match : matches) {
    correct += scene.edge_of_segment[match.view1][match.segment1] ==
                       scene.edge_of_segment[match.view2][match.segment2]
                   ? 1
                   : 0;
  }
  return matches.empty() ? 0.0 : static_cast<double>(correct) / matches.size();
}

TEST(PairwiseMatcher, MatchesSyntheticViewsWithExactPoses) {
  const SyntheticLineScene scene = MakeSyntheticLineScene({});
  const std::vector<MatchingView> views =
      MakeSyntheticViews(scene, scene.cam_from_world);
  LineMatchingOptions options;
  options.t_LBD = 100.0;
  PairwiseMatchingStats stats;
  const std::vector<PairwiseLineMatch> matches =
      MatchLinesPairwise(views, options, &stats);
  ASSERT_GT(matches.size(), 500u);
  EXPECT_GE(ShareCorrect(scene, matches), 0.99);
  EXPECT_EQ(stats.num_matches, matches.size());
  EXPECT_GT(stats.num_mutual_matches, matches.size() / 2);
  for (const PairwiseLineMatch& match : matches) {
    ASSERT_LT(match.view1, match.view2);
    ASSERT_GE(match.score, 0.0);
    ASSERT_LT(match.score, 4.0);
  }
  // Cross-check keeps exactly the mutual ones; one thread gives the same.
  options.cross_check = true;
  options.num_threads = 1;
  const std::vector<PairwiseLineMatch> mutual =
      MatchLinesPairwise(views, options);
  EXPECT_EQ(mutual.size(), stats.num_mutual_matches);
  for (const PairwiseLineMatch& match : mutual) EXPECT_TRUE(match.mutual);
}

TEST(PairwiseMatcher, DescriptorThresholdRejects) {
  SyntheticLineSceneOptions scene_options;
  scene_options.descriptor_bit_flips = 400;  // descriptors become random
  const SyntheticLineScene scene = MakeSyntheticLineScene(scene_options);
  const std::vector<MatchingView> views =
      MakeSyntheticViews(scene, scene.cam_from_world);
  LineMatchingOptions options;
  options.t_LBD = 60.0;
  EXPECT_LT(MatchLinesPairwise(views, options).size(), 20u);
}

}  // namespace
}  // namespace colmap_lidar
