#include "src/lines/workspace_line_extractor.h"

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/testing.h"
#include "src/dataset/importer.h"
#include "src/lidar/scan_io.h"

namespace colmap_lidar {
namespace {

// One KITTI workspace for all tests (importing is the slow part).
class KittiWorkspaceTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    workspace_ = new std::string(testing::CreateTestDir());
    ImporterOptions options;
    options.copy_images = false;
    options.copy_scans = false;
    summary_ = new ImportSummary(ImportDataset(
        testing::KittiSampleDir(), *workspace_, "", options));
  }
  static void TearDownTestSuite() {
    delete workspace_;
    delete summary_;
  }

  static std::string* workspace_;
  static ImportSummary* summary_;
};

std::string* KittiWorkspaceTest::workspace_ = nullptr;
ImportSummary* KittiWorkspaceTest::summary_ = nullptr;

TEST_F(KittiWorkspaceTest, ThreeFramesGiveSaneSegments) {
  std::vector<std::string> names;
  {
    Database database(summary_->database_path);
    for (const DatabaseImage& image : database.ReadAllImages()) {
      if (names.size() < 3) {
        names.push_back(image.name);
      }
    }
  }
  ASSERT_EQ(names.size(), 3u);
  LineExtractionOptions options;
  options.num_threads = 2;
  const std::string debug_path = JoinPaths(*workspace_, "lines_debug");
  const WorkspaceLineExtractionSummary summary = ExtractWorkspaceLines(
      summary_->database_path, summary_->image_path, names, options,
      debug_path);
  std::cout << summary.Format() << std::endl;
  EXPECT_EQ(summary.num_images, 3);
  // A sane count on a real urban frame: a few to tens of segments, not
  // thousands (4 to 5 on these first frames since range steps above 2% of
  // the range count as occlusions, see LidarEdgeOptions).
  EXPECT_GE(summary.min_segments_per_image, 4);
  EXPECT_LE(summary.max_segments_per_image, 400);
  EXPECT_GT(summary.num_lsd_segments, summary.num_lifted_segments);

  Database database(summary_->database_path);
  size_t total = 0;
  size_t num_plane_lifted = 0;
  for (const std::string& name : names) {
    const DatabaseImage image = *database.ReadImageWithName(name);
    const std::vector<LineSegmentRecord> segments =
        ReadLineSegments(database, image.image_id);
    total += segments.size();
    const Camera camera = *database.ReadCamera(image.camera_id);
    for (const LineSegmentRecord& segment : segments) {
      for (const Eigen::Vector3d& endpoint :
           {segment.start3D_in_cam, segment.end3D_in_cam}) {
        EXPECT_GT(endpoint.z(), 0.5) << name;
        EXPECT_LT(endpoint.norm(), 120.0) << name;
        // The 3D endpoint reprojects onto its 2D endpoint.
      }
      EXPECT_LT((camera.ImgFromCam(segment.start3D_in_cam) - segment.start2D)
                    .norm(),
                0.01);
      // Edge points of a segment they lifted; none when the planes on its
      // sides lifted it.
      EXPECT_TRUE(segment.num_inliers == 0u || segment.num_inliers >= 5u)
          << segment.num_inliers;
      num_plane_lifted += segment.num_inliers == 0u ? 1 : 0;
    }
    const std::string stem =
        JoinPaths(debug_path, std::filesystem::path(name).stem().string());
    EXPECT_TRUE(ExistsFile(stem + ".png")) << name;
    // Every LSD segment with its outcome; the lifted ones (before fusion)
    // at least as many as the stored ones, each with its 3D endpoints.
    const Json outcomes = ReadJsonFile(stem + ".json");
    EXPECT_EQ(outcomes["image_name"], name);
    ASSERT_EQ(outcomes["segments"].size(),
              outcomes["num_lsd_segments"].get<size_t>());
    size_t num_lifted = 0;
    for (const Json& segment : outcomes["segments"]) {
      const std::string edge_result = segment["edge_result"];
      const std::string plane_result = segment["plane_result"];
      EXPECT_NE(edge_result, "unknown");
      // The plane lifting tries every segment the edge points did not lift.
      EXPECT_EQ(plane_result == "not_tried", edge_result == "lifted")
          << edge_result << " / " << plane_result;
      // The surface test's verdict where it ran: an edge when lifted.
      const bool tested = edge_result == "lifted" || edge_result == "texture";
      ASSERT_EQ(segment.contains("edge_surface"), tested);
      if (edge_result == "lifted") {
        const std::string surface = segment["edge_surface"];
        EXPECT_TRUE(surface == "crease" || surface == "occlusion") << surface;
      } else if (tested) {
        EXPECT_NE(segment["edge_surface"], "crease");
      }
      if (edge_result == "lifted" || plane_result == "crease" ||
          plane_result == "occlusion") {
        ++num_lifted;
        ASSERT_TRUE(segment.contains("start3D_in_cam"));
        EXPECT_GT(segment["start3D_in_cam"][2].get<double>(), 0.0);
        EXPECT_GT(segment["end3D_in_cam"][2].get<double>(), 0.0);
      } else {
        EXPECT_FALSE(segment.contains("start3D_in_cam"));
      }
    }
    EXPECT_GE(num_lifted, outcomes["num_segments"].get<size_t>()) << name;
  }
  EXPECT_EQ(total, static_cast<size_t>(summary.num_segments));
  // On KITTI's traffic most segments have edge points; a few are lifted by
  // the planes alone.
  EXPECT_LT(num_plane_lifted, total / 2);

  // Re-running replaces the rows instead of adding to them.
  const size_t before = NumLineSegments(database);
  database.Close();
  ExtractWorkspaceLines(summary_->database_path, summary_->image_path,
                        {names[0]}, options);
  database.Open(summary_->database_path);
  EXPECT_EQ(NumLineSegments(database), before);
}

TEST_F(KittiWorkspaceTest, UnknownImageThrows) {
  EXPECT_THROW(ExtractWorkspaceLines(summary_->database_path,
                                     summary_->image_path, {"nope.png"},
                                     LineExtractionOptions()),
               Error);
}

}  // namespace
}  // namespace colmap_lidar
