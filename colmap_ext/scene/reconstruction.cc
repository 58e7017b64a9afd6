#include "colmap_ext/scene/reconstruction.h"

#include <set>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

const Image* Reconstruction::FindImage(image_t image_id) const {
  for (const Image& image : images) {
    if (image.image_id == image_id) {
      return &image;
    }
  }
  return nullptr;
}

Image* Reconstruction::FindImage(image_t image_id) {
  return const_cast<Image*>(
      static_cast<const Reconstruction*>(this)->FindImage(image_id));
}

const Image* Reconstruction::FindImageByName(const std::string& name) const {
  for (const Image& image : images) {
    if (image.name == name) {
      return &image;
    }
  }
  return nullptr;
}

Image* Reconstruction::FindImageByName(const std::string& name) {
  return const_cast<Image*>(
      static_cast<const Reconstruction*>(this)->FindImageByName(name));
}

int Reconstruction::ImageIndex(image_t image_id) const {
  for (size_t i = 0; i < images.size(); ++i) {
    if (images[i].image_id == image_id) {
      return static_cast<int>(i);
    }
  }
  return -1;
}

namespace {

template <typename Id, typename Value>
std::vector<Id> IdsInWriteOrder(const std::vector<Id>& file_order,
                                const std::map<Id, Value>& map) {
  std::vector<Id> ids;
  ids.reserve(map.size());
  std::set<Id> emitted;
  for (const Id id : file_order) {
    if (map.count(id) > 0 && emitted.insert(id).second) {
      ids.push_back(id);
    }
  }
  for (const auto& entry : map) {
    if (emitted.count(entry.first) == 0) {
      ids.push_back(entry.first);
    }
  }
  return ids;
}

}  // namespace

std::vector<camera_t> Reconstruction::CameraIdsInWriteOrder() const {
  return IdsInWriteOrder(camera_file_order, cameras);
}

std::vector<point3D_t> Reconstruction::Point3DIdsInWriteOrder() const {
  return IdsInWriteOrder(point3D_file_order, points3D);
}

void Reconstruction::CheckConsistency() const {
  std::map<image_t, const Image*> image_by_id;
  for (const Image& image : images) {
    THROW_CHECK(
        image_by_id.emplace(image.image_id, &image).second,
        "Duplicate image id " << image.image_id << " (" << image.name << ")");
    THROW_CHECK(cameras.count(image.camera_id) > 0,
                "Image " << image.image_id << " (" << image.name
                         << ") refers to missing camera " << image.camera_id);
    for (size_t i = 0; i < image.points2D.size(); ++i) {
      const point3D_t point3D_id = image.points2D[i].point3D_id;
      THROW_CHECK(
          point3D_id == kInvalidPoint3DId || points3D.count(point3D_id) > 0,
          "Image " << image.image_id << " point2D " << i
                   << " refers to missing 3D point " << point3D_id);
    }
  }
  for (const auto& [camera_id, camera] : cameras) {
    THROW_CHECK(camera.camera_id == camera_id, "Camera stored under id "
                                                   << camera_id << " has id "
                                                   << camera.camera_id);
  }
  for (const auto& [point3D_id, point3D] : points3D) {
    for (const TrackElement& element : point3D.track) {
      const auto it = image_by_id.find(element.image_id);
      THROW_CHECK(it != image_by_id.end(),
                  "3D point " << point3D_id << " observed by missing image "
                              << element.image_id);
      THROW_CHECK(element.point2D_idx < it->second->points2D.size(),
                  "3D point " << point3D_id << " refers to point2D "
                              << element.point2D_idx << " of image "
                              << element.image_id << " which has only "
                              << it->second->points2D.size());
      const point3D_t back_reference =
          it->second->points2D[element.point2D_idx].point3D_id;
      THROW_CHECK(back_reference == point3D_id,
                  "3D point " << point3D_id << " observes point2D "
                              << element.point2D_idx << " of image "
                              << element.image_id
                              << ", which refers to 3D point "
                              << static_cast<int64_t>(back_reference));
    }
  }
  for (const auto& [line3D_id, line3D] : lines3D) {
    for (const LineTrackElement& element : line3D.track) {
      THROW_CHECK(image_by_id.count(element.image_id) > 0,
                  "3D line " << line3D_id << " observed by missing image "
                             << element.image_id);
    }
  }
}

}  // namespace colmap_lidar
