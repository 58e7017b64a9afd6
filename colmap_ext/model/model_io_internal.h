// Helpers shared by the files that implement model_io.h (model_io.cc,
// model_io_binary.cc, model_io_text.cc); not part of the module's interface.
#pragma once

#include <string>

#include "colmap_ext/model/model_io.h"

namespace colmap_lidar {
namespace model_io_internal {

// Leaves bytes of an already unit quaternion untouched (colmap wrote it
// normalised; renormalising could change the last bit).
Eigen::Quaterniond NormalizedQuaternion(double w, double x, double y, double z,
                                        const std::string& where);

// Camera::Check with `where` (a path, or path:line) prefixed to its message.
void CheckCamera(const Camera& camera, const std::string& where);

// Throws naming `path` when the image name cannot be stored in `format`.
void CheckImageName(const Image& image, ModelFormat format,
                    const std::string& path);

}  // namespace model_io_internal
}  // namespace colmap_lidar
