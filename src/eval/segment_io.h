// 3D line segment files for the line evaluator.
//
// Accepted inputs (ReadSegments picks by path):
// - A folder holding a sparse model: the segments of its lines3D
//   (start_in_world, end_in_world), read with ReadReconstruction.
// - Text (any other extension, e.g. .txt): one segment per line,
//   "x1 y1 z1 x2 y2 z2" followed by any number of extra columns, which are
//   ignored (so the synthesizer's ground_truth/crease_edges.txt, which
//   appends normals, convexity and angle, reads as is); '#' starts a
//   comment line; blank lines are skipped.
// - .ply: with an "edge" element (properties vertex1, vertex2), each edge is
//   a segment between two vertices (ASCII or binary, any other elements are
//   skipped); without it, consecutive vertex pairs (0,1), (2,3), ... are the
//   segments and the vertex count must be even.
// - .obj: "v x y z" vertices and "l i j [k ...]" polylines (1-based indices,
//   negative ones relative), each consecutive pair a segment.
//
// Written format (WriteSegmentsPly): binary little-endian PLY, "element
// vertex 2N" with double x y z (segment i is vertices 2i, 2i+1) and
// "element edge N" with int vertex1 vertex2 — readable as a line set by
// CloudCompare and MeshLab, and by both PLY rules above.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace colmap_lidar {

struct Segment3D {
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  Eigen::Vector3d end = Eigen::Vector3d::Zero();

  double Length() const { return (end - start).norm(); }
};

// Throws colmap_lidar::Error naming the path (and line or element) on a
// missing file, a malformed line, a non-finite coordinate, an odd vertex
// count or an out-of-range index. An empty file is a value (no segments).
std::vector<Segment3D> ReadSegments(const std::string& path);

std::vector<Segment3D> ReadSegmentsText(const std::string& path);
std::vector<Segment3D> ReadSegmentsPly(const std::string& path);
std::vector<Segment3D> ReadSegmentsObj(const std::string& path);

// Atomic writers of the formats above.
void WriteSegmentsPly(const std::string& path,
                      const std::vector<Segment3D>& segments);
void WriteSegmentsText(const std::string& path,
                       const std::vector<Segment3D>& segments);

}  // namespace colmap_lidar
