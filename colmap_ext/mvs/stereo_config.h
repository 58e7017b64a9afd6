// The two configuration files of a dense workspace's stereo/ folder
// (colmap-formats.md 3.2, 3.3).
//
// patch-match.cfg: two-line records, a reference image name and then its
// source images: "__auto__, N" (the N best by shared sparse points),
// "__all__", or a comma-separated list of names. Lines are trimmed; blank
// lines and '#' comment lines are allowed before a reference name.
//
// fusion.cfg: one reference image name per line; lines are trimmed and blank
// lines skipped, but '#' is NOT a comment (COLMAP would look up an image
// called "# ..." and abort).
#pragma once

#include <string>
#include <vector>

namespace colmap_lidar {

struct PatchMatchEntry {
  enum class SourceKind { kAuto, kAll, kList };

  std::string ref_image_name;
  SourceKind source_kind = SourceKind::kAuto;
  // For kAuto: how many source images COLMAP picks (> 0).
  int num_auto_src_images = 20;
  // For kList: the source image names (not empty).
  std::vector<std::string> src_image_names;
};

// Throws colmap_lidar::Error naming the file and line on a missing file, a
// reference name without a sources line, a sources line that starts with '#',
// or a bad "__auto__" count. A reference with an empty source list is dropped
// with a warning, as COLMAP does.
std::vector<PatchMatchEntry> ReadPatchMatchConfig(const std::string& path);
// Atomic. Throws on a name that COLMAP would not read back unchanged (empty,
// leading/trailing white space, a line break, ',' or ';' in source names, a
// reference name starting with '#') or an empty source list.
void WritePatchMatchConfig(const std::string& path,
                           const std::vector<PatchMatchEntry>& entries);

// Throws naming the file when it is missing.
std::vector<std::string> ReadFusionConfig(const std::string& path);
// Atomic. Throws on an empty name, leading/trailing white space or a line
// break in a name.
void WriteFusionConfig(const std::string& path,
                       const std::vector<std::string>& image_names);

}  // namespace colmap_lidar
