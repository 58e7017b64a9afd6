// Counter-based random numbers for PatchMatch: every draw is a hash of
// (seed, iteration, pixel, draw index), so results do not depend on the
// number of threads or the order in which pixels are visited.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <Eigen/Core>

namespace colmap_lidar {

class PixelRandom {
 public:
  PixelRandom(uint64_t seed, uint64_t iteration, uint64_t pixel)
      : state_(Mix(seed * 0x9E3779B97F4A7C15ull ^ Mix(iteration + 1) ^
                   Mix(pixel * 0xD1B54A32D192ED03ull + 7))) {}
  // Uniform in [0, 1).
  float Uniform() {
    state_ += 0x9E3779B97F4A7C15ull;
    return static_cast<float>(Mix(state_) >> 40) * (1.0f / 16777216.0f);
  }
  float Uniform(float lo, float hi) { return lo + (hi - lo) * Uniform(); }
  // Uniform on the unit sphere.
  Eigen::Vector3f UnitVector() {
    const float z = Uniform(-1.0f, 1.0f);
    const float phi = Uniform(0.0f, 6.2831853f);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    return Eigen::Vector3f(r * std::cos(phi), r * std::sin(phi), z);
  }

 private:
  static uint64_t Mix(uint64_t x) {
    x ^= x >> 30;
    x *= 0xBF58476D1CE4E5B9ull;
    x ^= x >> 27;
    x *= 0x94D049BB133111EBull;
    x ^= x >> 31;
    return x;
  }
  uint64_t state_;
};

}  // namespace colmap_lidar
