// The distributed commands under MPI (issue 19): the real build/colmap-lidar
// started by `mpirun -np 2` (one thread per rank) on a workspace must leave
// exactly what one process leaves: the same ext_line_segments rows
// (line_extractor), the same depth, normal and fusion-mask files byte for
// byte (lidar_patch_match_stereo) and the same mesh by tiles
// (lidar_delaunay_mesher). A command that is not distributed refuses
// to run on two ranks, and a rank's bad input fails the whole job with the
// file named.
//
// The workspace is a small synthetic recording taken through the dense
// stage by automatic_reconstructor (about a minute).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "colmap_ext/database/database.h"
#include "colmap_ext/database/line_segments_table.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {
namespace fs = std::filesystem;

std::string Binary() { return JoinPaths(testing::BinaryDir(), "colmap-lidar"); }

// Two ranks on one machine, whatever the user and the core count; without
// the shared-memory single-copy mechanism, which containers that forbid
// ptrace between processes refuse.
std::string Mpirun() {
  return "mpirun --allow-run-as-root --oversubscribe"
         " --mca btl_vader_single_copy_mechanism none -np 2 ";
}

std::string ReadBytes(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(file), {});
}

// Relative path -> bytes of every regular file under `dir`.
std::vector<std::pair<std::string, std::string>> Files(const std::string& dir) {
  std::vector<std::pair<std::string, std::string>> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.is_regular_file()) {
      files.emplace_back(fs::relative(entry.path(), dir).string(),
                         ReadBytes(entry.path().string()));
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

class MpiRunsTest : public ::testing::Test {
 protected:
  // One workspace for the suite, through the dense stage.
  static void SetUpTestSuite() {
    root_ = new std::string(testing::CreateTestDir());
    const std::string workspace = JoinPaths(*root_, "ws");
    const std::string command =
        Binary() + " automatic_reconstructor --workspace_path " + workspace +
        " --AutomaticReconstruction.stages :dense"
        " --AutomaticReconstruction.num_threads 2"
        " --Synthesis.num_frames 8 --Synthesis.path_fraction 0.08"
        " --Synthesis.image_width 640 --Synthesis.image_height 360"
        " --Synthesis.supersampling 1 --Synthesis.lidar_columns 512"
        " --Synthesis.survey_angular_step_deg 0.4"
        " --Synthesis.survey_max_points 200000"
        " --Synthesis.write_depth_maps false";
    setup_exit_code_ =
        testing::RunCommand(command, JoinPaths(*root_, "setup.log"));
  }

  static void TearDownTestSuite() {
    delete root_;
    root_ = nullptr;
  }

  void SetUp() override {
    ASSERT_EQ(setup_exit_code_, 0)
        << "automatic_reconstructor failed, see " << *root_ << "/setup.log";
  }

  static std::string Workspace() { return JoinPaths(*root_, "ws"); }

  // A copy of the dense workspace without any depth map.
  static std::string CopyDense(const std::string& name) {
    const std::string copy = JoinPaths(*root_, name);
    fs::remove_all(copy);
    fs::copy(JoinPaths(Workspace(), "dense"), copy,
             fs::copy_options::recursive);
    for (const char* dir :
         {"stereo/depth_maps", "stereo/normal_maps", "stereo/fusion_masks",
          "stereo/consistency_graphs"}) {
      fs::remove_all(JoinPaths(copy, dir));
    }
    return copy;
  }

  static std::string* root_;
  static int setup_exit_code_;
};

std::string* MpiRunsTest::root_ = nullptr;
int MpiRunsTest::setup_exit_code_ = -1;

TEST_F(MpiRunsTest, LineExtractorOnTwoRanksWritesTheSameSegments) {
  std::vector<std::string> databases;
  for (const std::string& launcher : {std::string(), Mpirun()}) {
    // Beside the original: the scans' paths are relative to its folder.
    const std::string database = JoinPaths(
        Workspace(), launcher.empty() ? "one_rank.db" : "two_ranks.db");
    fs::copy_file(JoinPaths(Workspace(), "database.db"), database,
                  fs::copy_options::overwrite_existing);
    const std::string log = database + ".log";
    ASSERT_EQ(
        testing::RunCommand(
            launcher + Binary() + " line_extractor --database_path " +
                database + " --image_path " + JoinPaths(Workspace(), "images") +
                " --LineExtraction.num_threads 1",
            log),
        0)
        << ReadBytes(log);
    databases.push_back(database);
  }
  const Database one(databases[0]);
  const Database two(databases[1]);
  EXPECT_GT(NumLineSegments(one), 0u);
  EXPECT_EQ(NumLineSegments(one), NumLineSegments(two));
  for (const DatabaseImage& image : one.ReadAllImages()) {
    const std::vector<LineSegmentRecord> a =
        ReadLineSegments(one, image.image_id);
    const std::vector<LineSegmentRecord> b =
        ReadLineSegments(two, image.image_id);
    ASSERT_EQ(a.size(), b.size()) << image.name;
    for (size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].start2D, b[i].start2D) << image.name << " " << i;
      EXPECT_EQ(a[i].end2D, b[i].end2D) << image.name << " " << i;
      EXPECT_EQ(a[i].start3D_in_cam, b[i].start3D_in_cam) << image.name;
      EXPECT_EQ(a[i].end3D_in_cam, b[i].end3D_in_cam) << image.name;
      EXPECT_EQ(a[i].num_inliers, b[i].num_inliers) << image.name;
      EXPECT_EQ(a[i].descriptor, b[i].descriptor) << image.name;
    }
  }
  // The summary once, from rank 0, with every image.
  const std::string log = ReadBytes(databases[1] + ".log");
  size_t count = 0;
  for (size_t pos = log.find("Line extraction: 8 images");
       pos != std::string::npos;
       pos = log.find("Line extraction: 8 images", pos + 1)) {
    ++count;
  }
  EXPECT_EQ(count, 1u) << log;
}

TEST_F(MpiRunsTest, PatchMatchOnTwoRanksWritesTheSameMaps) {
  const std::string one = CopyDense("dense_one_rank");
  const std::string two = CopyDense("dense_two_ranks");
  const std::string options =
      " lidar_patch_match_stereo --LidarPatchMatch.num_threads 1"
      " --LidarPatchMatch.max_image_size 320 --workspace_path ";
  ASSERT_EQ(testing::RunCommand(Binary() + options + one, one + ".log"), 0)
      << ReadBytes(one + ".log");
  ASSERT_EQ(
      testing::RunCommand(Mpirun() + Binary() + options + two, two + ".log"), 0)
      << ReadBytes(two + ".log");
  const auto a = Files(JoinPaths(one, "stereo"));
  const auto b = Files(JoinPaths(two, "stereo"));
  ASSERT_EQ(a.size(), b.size());
  size_t num_maps = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].first, b[i].first);
    EXPECT_TRUE(a[i].second == b[i].second) << a[i].first << " differs";
    num_maps += a[i].first.find(".geometric.bin") != std::string::npos;
  }
  // Depth and normal maps of all 8 images.
  EXPECT_EQ(num_maps, 16u);
}

// Meshing by tiles (a budget far below the input's points) with the line
// samples (rank 0 alone reads their observations from the database): the
// tiles are meshed on both ranks and merged on rank 0 in one order, so the
// mesh is the one process's byte for byte.
TEST_F(MpiRunsTest, DelaunayMesherOnTwoRanksWritesTheSameMesh) {
  const std::string options =
      " lidar_delaunay_mesher --workspace_path " +
      JoinPaths(Workspace(), "dense") +
      " --lines_path " + JoinPaths(Workspace(), "sparse/refined") +
      " --database_path " + JoinPaths(Workspace(), "database.db") +
      " --DelaunayMeshing.use_visual false"
      " --DelaunayMeshing.max_memory_gb 0.02"
      " --DelaunayMeshing.tile_margin_m 2"
      " --DelaunayMeshing.num_threads 1 --output_path ";
  const std::string one = JoinPaths(*root_, "mesh_one_rank.ply");
  const std::string two = JoinPaths(*root_, "mesh_two_ranks.ply");
  ASSERT_EQ(testing::RunCommand(Binary() + options + one, one + ".log"), 0)
      << ReadBytes(one + ".log");
  ASSERT_EQ(
      testing::RunCommand(Mpirun() + Binary() + options + two, two + ".log"), 0)
      << ReadBytes(two + ".log");
  const std::string log = ReadBytes(two + ".log");
  EXPECT_NE(log.find(" tiles ("), std::string::npos) << log;
  EXPECT_NE(log.find("on 2 ranks"), std::string::npos) << log;
  EXPECT_NE(log.find("Line samples: "), std::string::npos) << log;
  const std::string a = ReadBytes(one);
  EXPECT_GT(a.size(), 100000u);
  EXPECT_TRUE(a == ReadBytes(two)) << "the meshes differ";
}

TEST_F(MpiRunsTest, OneRanksBadImageFailsTheJobNamingIt) {
  const std::string dense = CopyDense("dense_bad_image");
  // The second image goes to rank 1 (round robin).
  std::vector<std::string> images;
  for (const auto& entry : fs::directory_iterator(JoinPaths(dense, "images"))) {
    images.push_back(entry.path().string());
  }
  std::sort(images.begin(), images.end());
  ASSERT_GE(images.size(), 2u);
  fs::remove(images[1]);
  std::ofstream(images[1]) << "not an image";
  const std::string log = dense + ".log";
  EXPECT_NE(testing::RunCommand(Mpirun() + Binary() +
                                    " lidar_patch_match_stereo"
                                    " --LidarPatchMatch.num_threads 1"
                                    " --LidarPatchMatch.max_image_size 160"
                                    " --workspace_path " +
                                    dense,
                                log),
            0);
  const std::string text = ReadBytes(log);
  EXPECT_NE(text.find(fs::path(images[1]).filename().string()),
            std::string::npos)
      << text;
}

TEST_F(MpiRunsTest, OtherCommandsRefuseTwoRanks) {
  const std::string log = JoinPaths(*root_, "refused.log");
  EXPECT_NE(testing::RunCommand(Mpirun() + Binary() +
                                    " lidar_fuser --workspace_path " +
                                    JoinPaths(*root_, "nowhere"),
                                log),
            0);
  EXPECT_NE(ReadBytes(log).find("runs in one process"), std::string::npos)
      << ReadBytes(log);
}

}  // namespace
}  // namespace colmap_lidar
