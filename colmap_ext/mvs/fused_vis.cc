#include "colmap_ext/mvs/fused_vis.h"

#include <cstring>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

template <typename T>
T Take(const std::string& content, size_t* pos, const std::string& path) {
  THROW_CHECK(content.size() - *pos >= sizeof(T),
              "Truncated visibility file " << path << " at byte " << *pos);
  T value;
  std::memcpy(&value, content.data() + *pos, sizeof(T));
  *pos += sizeof(T);
  return value;
}

}  // namespace

FusedVisibility ReadFusedVis(const std::string& path) {
  CheckFileExists(path, "Fused visibility file");
  const std::string content = ReadTextFile(path);
  size_t pos = 0;
  const uint64_t num_points = Take<uint64_t>(content, &pos, path);
  // Each point needs at least its 4-byte count.
  THROW_CHECK(num_points <= (content.size() - pos) / 4,
              "Truncated visibility file " << path << ": " << num_points
                                           << " points declared in "
                                           << content.size() << " bytes");
  FusedVisibility visibility(num_points);
  for (uint64_t i = 0; i < num_points; ++i) {
    const uint32_t count = Take<uint32_t>(content, &pos, path);
    THROW_CHECK(count <= (content.size() - pos) / 4,
                "Truncated visibility file " << path << " at point " << i);
    visibility[i].resize(count);
    // An empty vector's data() may be null, which memcpy must not get.
    if (count > 0) {
      std::memcpy(visibility[i].data(), content.data() + pos, 4 * count);
    }
    pos += 4 * count;
  }
  THROW_CHECK(pos == content.size(), "Visibility file "
                                         << path << " has "
                                         << content.size() - pos
                                         << " trailing bytes");
  return visibility;
}

FusedVisibility ReadFusedVis(const std::string& path,
                             size_t expected_num_points) {
  FusedVisibility visibility = ReadFusedVis(path);
  THROW_CHECK(visibility.size() == expected_num_points,
              "Visibility file " << path << " has " << visibility.size()
                                 << " points, the PLY has "
                                 << expected_num_points);
  return visibility;
}

void WriteFusedVis(const std::string& path,
                   const FusedVisibility& visibility) {
  WriteFileAtomically(path, [&](std::ostream& stream) {
    WriteBinary<uint64_t>(stream, visibility.size());
    for (const std::vector<uint32_t>& image_idxs : visibility) {
      WriteBinary<uint32_t>(stream, static_cast<uint32_t>(image_idxs.size()));
      WriteBinaryArray(stream, image_idxs.data(), image_idxs.size());
    }
  });
}

void CheckFusedVisIndices(const FusedVisibility& visibility, size_t num_images,
                          const std::string& path_for_errors) {
  for (size_t i = 0; i < visibility.size(); ++i) {
    for (const uint32_t image_idx : visibility[i]) {
      THROW_CHECK(image_idx < num_images,
                  "Image index " << image_idx << " of point " << i << " in "
                                 << path_for_errors << " is not below "
                                 << num_images);
    }
  }
}

}  // namespace colmap_lidar
