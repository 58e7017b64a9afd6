// A COLMAP sparse model in memory: cameras, registered images in the order
// of the model file (that order defines fusion's image_idx, see
// colmap-formats.md 4.8), 3D points with tracks, and our 3D line tracks.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "colmap_ext/scene/camera.h"
#include "colmap_ext/scene/image.h"
#include "colmap_ext/scene/line3d.h"
#include "colmap_ext/scene/point3d.h"

namespace colmap_lidar {

class Reconstruction {
 public:
  std::map<camera_t, Camera> cameras;
  // Registered images, in file order.
  std::vector<Image> images;
  std::map<point3D_t, Point3D> points3D;
  // Our 3D line tracks (lines3D.bin/.txt); empty for a stock model.
  std::map<line3D_t, Line3D> lines3D;
  // Optional order of the cameras and points in the files they were read
  // from (colmap writes them in hash-map order). Writers emit the ids listed
  // here first, in this order, then the others by increasing id; ids no
  // longer in the maps are skipped. This lets a model that colmap wrote be
  // re-encoded byte for byte. Leave empty to write in id order.
  std::vector<camera_t> camera_file_order;
  std::vector<point3D_t> point3D_file_order;

  // nullptr when absent.
  const Image* FindImage(image_t image_id) const;
  Image* FindImage(image_t image_id);
  const Image* FindImageByName(const std::string& name) const;
  Image* FindImageByName(const std::string& name);
  // Position of the image in `images` (fusion's image_idx); -1 if absent.
  int ImageIndex(image_t image_id) const;

  // Ids in the order the writers use (see camera_file_order).
  std::vector<camera_t> CameraIdsInWriteOrder() const;
  std::vector<point3D_t> Point3DIdsInWriteOrder() const;

  // Throws colmap_lidar::Error on a broken reference: an image whose camera
  // is missing, a track element whose image or point2D index does not
  // exist, a point2D referring to a missing 3D point, a track element whose
  // point2D refers to another 3D point, duplicate image ids, a camera stored
  // under another id, a line track element whose image is missing.
  void CheckConsistency() const;
};

}  // namespace colmap_lidar
