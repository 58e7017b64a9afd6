#include "src/matching/relative_line_translation.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace colmap_lidar {
namespace relative_pose_internal {
namespace {

constexpr int kMaxTranslationPeaks = 12;
constexpr size_t kMaxSortedPeaks = 400;
constexpr int kPeakSeparationCells = 2;

}  // namespace

std::vector<Eigen::Vector3d> VoteLineTranslations(
    const LinePoseProblem& problem, const LineMatchingOptions& options,
    const Eigen::Matrix3d& rotation) {
  const std::vector<Line>& lines1 = problem.lines1;
  const std::vector<Line>& lines2 = problem.lines2;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Line& line : lines1) centroid += line.midpoint;
  centroid /= static_cast<double>(lines1.size());
  // The prior translation, moved so that the segments' centroid stays put
  // under the new rotation; the half size is the distance gate there.
  const Eigen::Vector3d center =
      problem.prior_translation + (problem.prior_rotation - rotation) * centroid;
  const double depth =
      (problem.prior_rotation * centroid + problem.prior_translation).z();
  const double cell = kTranslationVoteCellM;
  const double half_size =
      EffectiveThresholds(options, depth, problem.focal_length2).dO_m;
  const int size =
      std::max(1, static_cast<int>(std::ceil(2.0 * half_size / cell)));
  const Eigen::Vector3d origin = center - Eigen::Vector3d::Constant(half_size);
  const double extent = size * cell;
  std::vector<float> votes(static_cast<size_t>(size) * size * size, 0.0f);
  const auto index_of = [&](int x, int y, int z) {
    return (static_cast<size_t>(z) * size + y) * size + x;
  };
  for (const Candidate& c : problem.candidates) {
    const Eigen::Vector3d point =
        lines2[c.b].midpoint - rotation * lines1[c.a].midpoint - origin;
    const Eigen::Vector3d& direction = c.direction_b;
    // Clip the line to the grid box (slabs).
    double s_min = -std::numeric_limits<double>::infinity();
    double s_max = std::numeric_limits<double>::infinity();
    bool inside = true;
    for (int k = 0; k < 3 && inside; ++k) {
      if (std::abs(direction(k)) < 1e-12) {
        inside = point(k) >= 0.0 && point(k) < extent;
        continue;
      }
      double s0 = -point(k) / direction(k);
      double s1 = (extent - point(k)) / direction(k);
      if (s0 > s1) std::swap(s0, s1);
      s_min = std::max(s_min, s0);
      s_max = std::min(s_max, s1);
    }
    if (!inside || !(s_min < s_max)) continue;
    size_t last = std::numeric_limits<size_t>::max();
    for (double s = s_min; s < s_max; s += cell) {
      const Eigen::Vector3d q = (point + s * direction) / cell;
      const int x = std::clamp(static_cast<int>(q.x()), 0, size - 1);
      const int y = std::clamp(static_cast<int>(q.y()), 0, size - 1);
      const int z = std::clamp(static_cast<int>(q.z()), 0, size - 1);
      const size_t index = index_of(x, y, z);
      if (index == last) continue;
      votes[index] += 1.0f;
      last = index;
    }
  }
  // Local maxima of the 3x3x3 box sums (a line crossing a cell corner
  // votes in a neighbour), strongest first.
  struct Peak {
    float score;
    int x, y, z;
  };
  std::vector<Peak> peaks;
  const auto box_sum = [&](int x, int y, int z) {
    float sum = 0.0f;
    for (int dz = -1; dz <= 1; ++dz) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = y + dy, zz = z + dz;
          if (xx < 0 || yy < 0 || zz < 0 || xx >= size || yy >= size ||
              zz >= size) {
            continue;
          }
          sum += votes[index_of(xx, yy, zz)];
        }
      }
    }
    return sum;
  };
  for (int z = 0; z < size; ++z) {
    for (int y = 0; y < size; ++y) {
      for (int x = 0; x < size; ++x) {
        // A solution needs two non-parallel lines through its cell.
        if (votes[index_of(x, y, z)] < 2.0f) continue;
        peaks.push_back({box_sum(x, y, z), x, y, z});
      }
    }
  }
  // Only the strongest few hundred can make the cut.
  const auto stronger = [](const Peak& a, const Peak& b) {
    return a.score > b.score;
  };
  if (peaks.size() > kMaxSortedPeaks) {
    std::nth_element(peaks.begin(), peaks.begin() + kMaxSortedPeaks,
                     peaks.end(), stronger);
    peaks.resize(kMaxSortedPeaks);
  }
  std::sort(peaks.begin(), peaks.end(), stronger);
  std::vector<Eigen::Vector3d> translations;
  std::vector<Peak> kept;
  for (const Peak& peak : peaks) {
    bool separate = true;
    for (const Peak& other : kept) {
      separate &=
          std::max({std::abs(peak.x - other.x), std::abs(peak.y - other.y),
                    std::abs(peak.z - other.z)}) > kPeakSeparationCells;
    }
    if (!separate) continue;
    kept.push_back(peak);
    translations.push_back(origin + cell * Eigen::Vector3d(peak.x + 0.5,
                                                           peak.y + 0.5,
                                                           peak.z + 0.5));
    if (static_cast<int>(kept.size()) >= kMaxTranslationPeaks) break;
  }
  return translations;
}

}  // namespace relative_pose_internal
}  // namespace colmap_lidar
