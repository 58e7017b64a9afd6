// WriteLines3DPly (lidar_mapper.h): the model's 3D segments as a PLY line
// set, read back with the project's PLY readers.
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/testing.h"
#include "src/eval/segment_io.h"
#include "src/sfm/lidar_mapper.h"

namespace colmap_lidar {
namespace {

// The count of an "element <name> N" header line; -1 when there is none.
int ElementCount(const std::string& path, const std::string& name) {
  const std::string text = ReadTextFile(path);
  std::istringstream header(text.substr(0, text.find("end_header")));
  std::string line;
  while (std::getline(header, line)) {
    std::istringstream fields(line);
    std::string keyword, element;
    int count = -1;
    if (fields >> keyword >> element >> count && keyword == "element" &&
        element == name) {
      return count;
    }
  }
  return -1;
}

TEST(Lines3DPly, WritesOneEdgeBetweenTwoVerticesPerLine) {
  Reconstruction model;
  // Ids out of insertion order: the file follows the id order.
  const std::vector<std::pair<line3D_t, Segment3D>> lines = {
      {7, {Eigen::Vector3d(1.5, -2.25, 3.0),
           Eigen::Vector3d(4.0, 5.0, -6.125)}},
      {2, {Eigen::Vector3d(0.1, 0.2, 0.3),
           Eigen::Vector3d(-0.4, 1.0 / 3.0, 9.0)}},
      {11, {Eigen::Vector3d(-1e3, 2e-3, 0.0),
            Eigen::Vector3d(1e3, 0.0, -2e-3)}}};
  for (const auto& [id, segment] : lines) {
    Line3D line3D;
    line3D.start_in_world = segment.start;
    line3D.end_in_world = segment.end;
    model.lines3D[id] = line3D;
  }
  const std::string path = JoinPaths(testing::CreateTestDir(), "lines3D.ply");
  WriteLines3DPly(path, model);

  EXPECT_EQ(ElementCount(path, "vertex"), 6);
  EXPECT_EQ(ElementCount(path, "edge"), 3);
  const PlyData ply = ReadPly(path);
  ASSERT_EQ(ply.NumVertices(), 6u);
  const std::vector<Eigen::Vector3d> vertices = ply.Positions(path);
  // Line 2, then 7, then 11; start then end; doubles written exactly.
  const std::vector<line3D_t> order = {2, 7, 11};
  for (size_t i = 0; i < order.size(); ++i) {
    const Line3D& line3D = model.lines3D.at(order[i]);
    EXPECT_EQ(vertices[2 * i], line3D.start_in_world) << "line " << order[i];
    EXPECT_EQ(vertices[2 * i + 1], line3D.end_in_world) << "line " << order[i];
  }
  // The edge element makes the same segments.
  const std::vector<Segment3D> segments = ReadSegmentsPly(path);
  ASSERT_EQ(segments.size(), 3u);
  for (size_t i = 0; i < order.size(); ++i) {
    EXPECT_EQ(segments[i].start, model.lines3D.at(order[i]).start_in_world);
    EXPECT_EQ(segments[i].end, model.lines3D.at(order[i]).end_in_world);
  }
}

TEST(Lines3DPly, ModelWithoutLinesGivesAnEmptyLineSet) {
  const std::string path = JoinPaths(testing::CreateTestDir(), "empty.ply");
  WriteLines3DPly(path, Reconstruction());
  EXPECT_EQ(ElementCount(path, "vertex"), 0);
  EXPECT_EQ(ElementCount(path, "edge"), 0);
  EXPECT_EQ(ReadPly(path).NumVertices(), 0u);
  EXPECT_TRUE(ReadSegmentsPly(path).empty());
}

}  // namespace
}  // namespace colmap_lidar
