// Camera image and ground-truth depth map of one frame, ray traced.
//
// Any COLMAP camera model is rendered as the DISTORTED image it describes:
// the ray of an image point (x, y) is the model's undistortion
// CamFromImg(x, y) = (u, v, 1) in the camera frame (iterative for the
// distorted models, camera_models.h), rotated into the world.
//
// Image: per pixel supersampling x supersampling rays through points on a
// regular grid inside the pixel (COLMAP's SfM convention: pixel (col, row)
// covers [col, col + 1] x [row, row + 1], its centre is (col + 0.5,
// row + 0.5)), box-filtered in linear radiance. Shading is Lambertian: a
// sun (direction from options, hard shadows by shadow rays) plus a sky
// ambient term that
// grows with the upward component of the normal; the procedural albedo
// comes from textures.h; misses show a sky gradient. The result is gamma
// encoded (1/2.2), gets Gaussian sensor noise (seeded per frame and pixel)
// and is quantised to 8-bit RGB.
//
// Depth map: one ray per pixel through the image point (col, row) WITHOUT
// the +0.5 (COLMAP's MVS convention, colmap-formats.md 4.4), for the same
// distorted camera: X_cam = depth * CamFromImg(col, row) (for PINHOLE
// depth * K^-1 [col, row, 1]). The value is the camera-frame z of the hit
// (not the ray length), 0 where the ray hits nothing.
#pragma once

#include <cstdint>

#include <opencv2/core.hpp>

#include "colmap_ext/scene/camera.h"
#include "colmap_ext/scene/rigid3.h"
#include "src/synth/ray_tracer.h"
#include "src/synth/synthesis_options.h"

namespace colmap_lidar {

struct RenderedFrame {
  cv::Mat image;  // CV_8UC3, BGR channel order (OpenCV's, for cv::imwrite).
  cv::Mat depth;  // CV_32FC1 z-depth in metres; empty unless requested.
};

// Unit vector towards the sun from the options' elevation and azimuth.
Eigen::Vector3d SunDirection(const SynthesisOptions& options);

// Throws colmap_lidar::Error when the camera is invalid (Camera::Check).
// The distortion must be invertible over the image (see
// SynthCameraProblem in synthesize.h), otherwise rays near the border are
// wrong.
// `frame_index` keys the image noise. Uses options.num_threads threads.
RenderedFrame RenderFrame(const RayTracer& tracer, const Camera& camera,
                          const Rigid3d& world_from_cam,
                          const SynthesisOptions& options, int frame_index,
                          bool render_depth);

}  // namespace colmap_lidar
