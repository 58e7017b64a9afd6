#include "src/eval/segment_io.h"

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

std::vector<Segment3D> Segments() {
  std::vector<Segment3D> segments(3);
  segments[0].start = {0.1, 0.2, 0.3};
  segments[0].end = {1.0 / 3.0, 5, -6};
  segments[1].start = {-1e5, 2e5, 3.25};
  segments[1].end = {-1e5 + 1, 2e5, 3.25};
  segments[2].start = {7, 8, 9};
  segments[2].end = {7, 8, 9.5};
  return segments;
}

void ExpectSame(const std::vector<Segment3D>& a,
                const std::vector<Segment3D>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].start, b[i].start) << i;
    EXPECT_EQ(a[i].end, b[i].end) << i;
  }
}

void WriteText(const std::string& path, const std::string& text) {
  WriteFileAtomically(path, [&](std::ostream& out) { out << text; }, false);
}

TEST(SegmentIo, PlyRoundTripWithEdgeElement) {
  const std::string path = JoinPaths(testing::CreateTestDir(), "s.ply");
  WriteSegmentsPly(path, Segments());
  ExpectSame(ReadSegments(path), Segments());
  // The stock PLY reader sees the 6 vertices (and skips the edges).
  EXPECT_EQ(ReadPly(path).NumVertices(), 6u);
  const std::string header = ReadTextFile(path).substr(0, 300);
  EXPECT_NE(header.find("element edge 3\nproperty int vertex1\n"),
            std::string::npos);
}

TEST(SegmentIo, TextRoundTripAndExtraColumns) {
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "s.txt");
  WriteSegmentsText(path, Segments());
  ExpectSame(ReadSegments(path), Segments());
  // The synthesizer's crease_edges.txt: normals, convexity, angle appended.
  const std::string crease = JoinPaths(dir, "crease_edges.txt");
  WriteText(crease,
            "# header\n\n0 0 0 1 0 0 0 0 1 0 1 0 1 90\n"
            "  2 2 2 2 2 3 1 0 0 0 1 0 0 90\n");
  const std::vector<Segment3D> edges = ReadSegments(crease);
  ASSERT_EQ(edges.size(), 2u);
  EXPECT_EQ(edges[1].start, Eigen::Vector3d(2, 2, 2));
  EXPECT_EQ(edges[1].end, Eigen::Vector3d(2, 2, 3));
  // Errors name the file and line.
  const std::string bad = JoinPaths(dir, "bad.txt");
  WriteText(bad, "0 0 0 1 0 0\n0 0 0 1 0\n");
  try {
    ReadSegments(bad);
    ADD_FAILURE();
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("line 2"), std::string::npos)
        << error.what();
  }
  WriteText(bad, "0 0 0 1 nan 0\n");
  EXPECT_THROW(ReadSegments(bad), Error);
  EXPECT_THROW(ReadSegments(JoinPaths(dir, "missing.txt")), Error);
}

TEST(SegmentIo, AsciiPlyWithSharedVerticesAndFaces) {
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "edges.ply");
  // A face element before the edges must be skipped correctly.
  WriteText(path,
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
            "property float y\nproperty float z\nelement face 1\n"
            "property list uchar int vertex_indices\nelement edge 2\n"
            "property int vertex1\nproperty int vertex2\n"
            "property uchar red\nend_header\n"
            "0 0 0\n1 0 0\n1 1 0\n3 0 1 2\n0 1 255\n1 2 0\n");
  const std::vector<Segment3D> segments = ReadSegments(path);
  ASSERT_EQ(segments.size(), 2u);
  EXPECT_EQ(segments[0].end, Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(segments[1].start, Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(segments[1].end, Eigen::Vector3d(1, 1, 0));

  // Without an edge element: vertex pairs; an odd count is an error.
  const std::string pairs = JoinPaths(dir, "pairs.ply");
  WriteText(pairs,
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
            "property float y\nproperty float z\nend_header\n"
            "0 0 0\n1 0 0\n1 1 0\n");
  EXPECT_THROW(ReadSegments(pairs), Error);
  const std::string out_of_range = JoinPaths(dir, "range.ply");
  WriteText(out_of_range,
            "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
            "property float y\nproperty float z\nelement edge 1\n"
            "property int vertex1\nproperty int vertex2\nend_header\n"
            "0 0 0\n1 0 0\n0 2\n");
  EXPECT_THROW(ReadSegments(out_of_range), Error);
}

TEST(SegmentIo, Obj) {
  const std::string path = JoinPaths(testing::CreateTestDir(), "l.obj");
  WriteText(path, "# polyline\nv 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2 3\nl -1 -3\n");
  const std::vector<Segment3D> segments = ReadSegments(path);
  ASSERT_EQ(segments.size(), 3u);
  EXPECT_EQ(segments[1].end, Eigen::Vector3d(1, 1, 0));
  EXPECT_EQ(segments[2].start, Eigen::Vector3d(1, 1, 0));
  EXPECT_EQ(segments[2].end, Eigen::Vector3d(0, 0, 0));
}

}  // namespace
}  // namespace colmap_lidar
