// A COLMAP-like SIFT descriptor for the matchers' tests.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

#include <Eigen/Core>

namespace colmap_lidar {

// Non-negative, L2 norm about 512 (COLMAP's uint8 SIFT descriptors).
inline Eigen::Matrix<uint8_t, 1, 128> RandomSiftDescriptor(std::mt19937* rng) {
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  Eigen::Matrix<float, 1, 128> values;
  for (int k = 0; k < 128; ++k) values(k) = std::pow(uniform(*rng), 3.0f);
  values *= 512.0f / values.norm();
  return values.array().round().min(255.0f).cast<uint8_t>();
}

}  // namespace colmap_lidar
