#include "src/eval/eval_stats.h"

#include <algorithm>
#include <cmath>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

ErrorStats ComputeErrorStats(std::vector<double> values) {
  ErrorStats stats;
  stats.count = values.size();
  if (values.empty()) {
    return stats;
  }
  double sum = 0.0;
  double sum_squared = 0.0;
  for (const double value : values) {
    sum += value;
    sum_squared += value * value;
    stats.max = std::max(stats.max, value);
  }
  stats.mean = sum / values.size();
  stats.rmse = std::sqrt(sum_squared / values.size());
  const size_t middle = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + middle, values.end());
  stats.median = values[middle];
  if (values.size() % 2 == 0) {
    const double lower =
        *std::max_element(values.begin(), values.begin() + middle);
    stats.median = 0.5 * (stats.median + lower);
  }
  return stats;
}

double ShareBelow(const std::vector<double>& values, double threshold,
                  const std::vector<double>& weights, double denominator) {
  THROW_CHECK(weights.empty() || weights.size() == values.size(),
              "ShareBelow: " << weights.size() << " weights for "
                             << values.size() << " values");
  double below = 0.0;
  double total = 0.0;
  for (size_t i = 0; i < values.size(); ++i) {
    const double weight = weights.empty() ? 1.0 : weights[i];
    total += weight;
    if (values[i] < threshold) {
      below += weight;
    }
  }
  if (denominator < 0.0) {
    denominator = total;
  }
  return denominator > 0.0 ? below / denominator : 0.0;
}

double FScore(double precision, double recall) {
  const double sum = precision + recall;
  return sum > 0.0 ? 2.0 * precision * recall / sum : 0.0;
}

bool CheckThresholds(const std::vector<double>& thresholds,
                     const std::string& option_name) {
  if (thresholds.empty()) {
    LOG(ERROR) << option_name << " must list at least one threshold";
    return false;
  }
  for (size_t i = 0; i < thresholds.size(); ++i) {
    if (!std::isfinite(thresholds[i]) || thresholds[i] <= 0.0) {
      LOG(ERROR) << option_name << " must be positive and finite, got "
                 << thresholds[i];
      return false;
    }
    if (i > 0 && thresholds[i] <= thresholds[i - 1]) {
      LOG(ERROR) << option_name << " must be strictly increasing, got "
                 << thresholds[i - 1] << " before " << thresholds[i];
      return false;
    }
  }
  return true;
}

}  // namespace colmap_lidar
