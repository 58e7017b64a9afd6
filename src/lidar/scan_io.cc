// The format dispatch of scan_io.h and the reader contract shared by all
// formats (finite points, no-return points dropped); the formats are in
// scan_io_ply.cc, scan_io_pcd.cc and scan_io_kitti.cc.
#include "src/lidar/scan_io.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/string.h"
#include "src/lidar/scan_io_internal.h"

namespace colmap_lidar {
namespace {

using scan_io_internal::CheckPcdHeader;
using scan_io_internal::CountPlyScanPoints;
using scan_io_internal::KittiBinNumPoints;
using scan_io_internal::ReadKittiBinScan;
using scan_io_internal::ReadPcdScan;
using scan_io_internal::ReadPlyScan;

constexpr char kAcceptedExtensions[] = ".ply, .pcd, .bin (KITTI)";

enum class ScanFormat { kPly, kPcd, kKittiBin };

ScanFormat FormatFromPath(const std::string& path) {
  const std::string extension =
      StringToLower(std::filesystem::path(path).extension().string());
  if (extension == ".ply") {
    return ScanFormat::kPly;
  } else if (extension == ".pcd") {
    return ScanFormat::kPcd;
  } else if (extension == ".bin") {
    return ScanFormat::kKittiBin;
  }
  THROW_ERROR("Unsupported LIDAR scan file " << path << ": the extension '"
                                             << extension
                                             << "' is not one of "
                                             << kAcceptedExtensions);
}

// Checks finiteness and drops the no-return points at the origin (see the
// header), keeping the optional channels aligned.
void FinalizeScan(const std::string& path, LidarScan* scan) {
  const size_t num_read = scan->points.size();
  THROW_CHECK(num_read > 0, "LIDAR scan " << path << " has no points");
  size_t num_kept = 0;
  for (size_t i = 0; i < num_read; ++i) {
    const Eigen::Vector3f& point = scan->points[i];
    THROW_CHECK(point.allFinite(),
                "LIDAR scan " << path << " has a non-finite coordinate at point "
                              << i << " (" << point.transpose() << ")");
    if (point.x() == 0.f && point.y() == 0.f && point.z() == 0.f) {
      continue;
    }
    scan->points[num_kept] = point;
    if (scan->HasIntensities()) {
      scan->intensities[num_kept] = scan->intensities[i];
    }
    if (scan->HasRings()) {
      scan->rings[num_kept] = scan->rings[i];
    }
    ++num_kept;
  }
  if (num_kept == num_read) {
    return;
  }
  THROW_CHECK(num_kept > 0, "LIDAR scan " << path << " has only no-return "
                                          << "points at the origin");
  scan->points.resize(num_kept);
  if (scan->HasIntensities()) {
    scan->intensities.resize(num_kept);
  }
  if (scan->HasRings()) {
    scan->rings.resize(num_kept);
  }
  LOG(INFO) << "Dropped " << num_read - num_kept
            << " no-return points at the origin of " << path << " ("
            << num_kept << " kept)";
}

}  // namespace

namespace scan_io_internal {

uint16_t ToRing(const double value, const size_t index,
                const std::string& path) {
  THROW_CHECK(std::isfinite(value) && value >= 0 && value <= 65535 &&
                  value == std::floor(value),
              "Invalid ring " << value << " at point " << index << " in "
                              << path << " (expected an integer in [0, "
                              << "65535])");
  return static_cast<uint16_t>(value);
}

std::vector<std::vector<std::string>> ReadHeaderLines(
    const std::string& path, const std::string& last_keyword,
    size_t* header_bytes) {
  std::ifstream file(path, std::ios::binary);
  THROW_CHECK(file.is_open(), "Cannot open LIDAR scan " << path);
  std::vector<std::vector<std::string>> lines;
  std::string line;
  size_t num_bytes = 0;
  // Headers are short; the limit stops a binary file without header.
  while (lines.size() < 1000 && std::getline(file, line)) {
    std::vector<std::string> words;
    for (const std::string& word : StringSplit(StringTrim(line), " \t")) {
      if (!word.empty()) {
        words.push_back(word);
      }
    }
    lines.push_back(words);
    num_bytes += line.size() + 1;
    if (!words.empty() && words[0] == last_keyword) {
      if (header_bytes != nullptr) {
        *header_bytes = num_bytes;
      }
      return lines;
    }
  }
  THROW_ERROR("Cannot parse the header of " << path << ": no '"
                                            << last_keyword << "' line");
}

}  // namespace scan_io_internal

LidarScan ReadLidarScan(const std::string& path) {
  const ScanFormat format = FormatFromPath(path);
  CheckFileExists(path, "LIDAR scan");
  LidarScan scan;
  switch (format) {
    case ScanFormat::kPly:
      scan = ReadPlyScan(path);
      break;
    case ScanFormat::kPcd:
      scan = ReadPcdScan(path);
      break;
    case ScanFormat::kKittiBin:
      scan = ReadKittiBinScan(path);
      break;
  }
  FinalizeScan(path, &scan);
  return scan;
}

size_t CountLidarScanPoints(const std::string& path) {
  const ScanFormat format = FormatFromPath(path);
  CheckFileExists(path, "LIDAR scan");
  switch (format) {
    case ScanFormat::kPly:
      return CountPlyScanPoints(path);
    case ScanFormat::kPcd:
      return CheckPcdHeader(path);
    case ScanFormat::kKittiBin:
      return KittiBinNumPoints(path);
  }
  return 0;
}

}  // namespace colmap_lidar
