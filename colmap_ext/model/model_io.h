// Reading and writing COLMAP 3.8 sparse models (cameras, images, points3D in
// .bin or .txt, see colmap-formats.md section 2) plus our lines3D files,
// byte-compatible with the stock `colmap` binary.
//
// COLMAP files, exactly as colmap writes them:
// - cameras.bin: uint64 num_cameras; per camera uint32 camera_id, int32
//   model_id, uint64 width, uint64 height, float64 x num_params.
// - images.bin: uint64 num_images; per image uint32 image_id, float64 qw qx
//   qy qz tx ty tz (cam_from_world), uint32 camera_id, NUL-terminated name,
//   uint64 num_points2D, num_points2D x {float64 x, float64 y, uint64
//   point3D_id (2^64-1 = none)}.
// - points3D.bin: uint64 num_points; per point uint64 point3D_id, float64 x
//   y z, uint8 r g b, float64 error, uint64 track_length, track_length x
//   {uint32 image_id, uint32 point2D_idx}.
// - Text: '#' comment headers like colmap's, single spaces, 17 significant
//   digits, two lines per image (the second, possibly empty, holds
//   "X Y POINT3D_ID" triplets with -1 for none).
//
// Our 3D lines (stock colmap ignores these files):
// - lines3D.bin: uint64 num_lines; per line uint64 line3D_id, float64 x 6
//   (start xyz, end xyz, world frame), float64 error (px, -1 unknown),
//   uint64 track_length, track_length x {uint32 image_id, uint32
//   line2D_idx}. Little-endian, no padding.
// - lines3D.txt: a '#' comment header, then one line per 3D line:
//   "LINE3D_ID SX SY SZ EX EY EZ ERROR IMAGE_ID LINE2D_IDX ..." with the same
//   number formatting as colmap's text files.
//
// Order: images are read and written in file order (the order defines
// fusion's image_idx). Cameras and points keep their file order through
// Reconstruction::camera_file_order / point3D_file_order, so re-encoding a
// model colmap wrote reproduces its bytes. Quaternions are normalised on
// read only when they are not already unit (to 1e-12), so that bytes survive.
//
// Errors: every reader throws colmap_lidar::Error naming the file on
// truncation, trailing bytes, unknown camera models, wrong parameter counts,
// non-finite values, duplicate ids or malformed text. Readers do not check
// cross references (colmap's stereo_fusion writes models with dangling
// point references); call Reconstruction::CheckConsistency for that.
#pragma once

#include <string>

#include "colmap_ext/scene/reconstruction.h"

namespace colmap_lidar {

enum class ModelFormat { kBinary, kText };

// The format ReadReconstruction would pick for `dir`: binary when cameras,
// images and points3D .bin all exist, else text when the three .txt exist.
// Throws naming the folder when neither complete set exists.
ModelFormat DetectModelFormat(const std::string& dir);
// True when `dir` holds a complete .bin or .txt model.
bool ExistsModel(const std::string& dir);

// Reads the model in `dir` (format chosen by DetectModelFormat, the rule of
// colmap's Reconstruction::Read: binary wins when both exist), plus
// lines3D.bin or lines3D.txt if present in the chosen format (a lines3D file
// of the other format is ignored with a warning).
Reconstruction ReadReconstruction(const std::string& dir);

// Writes cameras, images, points3D and, when non-empty, lines3D in `format`,
// each file atomically; creates `dir` if needed. Throws if the model fails
// Reconstruction::CheckConsistency, a camera fails Camera::Check, or a name
// cannot be stored (NUL byte; white space or empty in text).
// Afterwards `dir` holds exactly this model: model files of the other format
// (cameras/images/points3D/lines3D .bin or .txt, which would otherwise win
// or go stale) and a stale lines3D file are removed, after the new files are
// in place. Other files (project.ini) are left alone.
void WriteReconstruction(const std::string& dir,
                         const Reconstruction& reconstruction,
                         ModelFormat format);

// Per-file readers: replace the corresponding members of `reconstruction`
// (cameras + camera_file_order, images, points3D + point3D_file_order,
// lines3D) with the file's content.
void ReadCamerasBinary(const std::string& path, Reconstruction* reconstruction);
void ReadImagesBinary(const std::string& path, Reconstruction* reconstruction);
void ReadPoints3DBinary(const std::string& path,
                        Reconstruction* reconstruction);
void ReadLines3DBinary(const std::string& path, Reconstruction* reconstruction);
void ReadCamerasText(const std::string& path, Reconstruction* reconstruction);
void ReadImagesText(const std::string& path, Reconstruction* reconstruction);
void ReadPoints3DText(const std::string& path, Reconstruction* reconstruction);
void ReadLines3DText(const std::string& path, Reconstruction* reconstruction);

// Per-file writers (atomic). They validate what the file needs (cameras,
// names) but not cross references.
void WriteCamerasBinary(const std::string& path,
                        const Reconstruction& reconstruction);
void WriteImagesBinary(const std::string& path,
                       const Reconstruction& reconstruction);
void WritePoints3DBinary(const std::string& path,
                         const Reconstruction& reconstruction);
void WriteLines3DBinary(const std::string& path,
                        const Reconstruction& reconstruction);
void WriteCamerasText(const std::string& path,
                      const Reconstruction& reconstruction);
void WriteImagesText(const std::string& path,
                     const Reconstruction& reconstruction);
void WritePoints3DText(const std::string& path,
                       const Reconstruction& reconstruction);
void WriteLines3DText(const std::string& path,
                      const Reconstruction& reconstruction);

}  // namespace colmap_lidar
