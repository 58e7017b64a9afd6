// Counter-based random numbers for the synthesiser. Every random value is a
// pure function of (seed, stream, index), so that the output does not depend
// on the number of threads or on the order in which pixels, rays or frames
// are processed: the same seed always gives the same dataset, bit for bit.
#pragma once

#include <cmath>
#include <cstdint>

namespace colmap_lidar {

// SplitMix64 finaliser: a bijective 64-bit mix with good avalanche.
inline uint64_t MixBits(uint64_t value) {
  value += 0x9E3779B97F4A7C15ULL;
  value = (value ^ (value >> 30)) * 0xBF58476D1CE4E5B9ULL;
  value = (value ^ (value >> 27)) * 0x94D049BB133111EBULL;
  return value ^ (value >> 31);
}

inline uint64_t HashCombine(uint64_t a, uint64_t b) {
  return MixBits(a ^ (MixBits(b) + 0x632BE59BD9B4E019ULL + (a << 6) + (a >> 2)));
}

// Streams of random numbers keyed by a seed and a stream id (frame, purpose).
class CounterRng {
 public:
  CounterRng(uint64_t seed, uint64_t stream)
      : key_(HashCombine(MixBits(seed), stream)) {}

  // Uniform in [0, 1) for the given index.
  double Uniform(uint64_t index) const {
    return static_cast<double>(HashCombine(key_, index) >> 11) *
           (1.0 / 9007199254740992.0);
  }

  // Standard normal for the given index (Box-Muller on two uniforms).
  double Normal(uint64_t index) const {
    const double u1 = 1.0 - Uniform(2 * index);  // In (0, 1].
    const double u2 = Uniform(2 * index + 1);
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }

 private:
  uint64_t key_;
};

// Purposes of the random streams; combined with a frame index where needed.
enum class RandomStream : uint64_t {
  kTrajectory = 1,
  kPriorNoise = 2,
  kLidarNoise = 3,
  kImageNoise = 4,
  kSurveyNoise = 5,
  kSurveySubsample = 6,
  kSceneLayout = 7,
  kLidarDropout = 8,
};

inline uint64_t StreamId(RandomStream stream, uint64_t index = 0) {
  return HashCombine(static_cast<uint64_t>(stream), index);
}

}  // namespace colmap_lidar
