// Summary statistics and threshold bookkeeping shared by the evaluators.
#pragma once

#include <string>
#include <vector>

namespace colmap_lidar {

// Statistics of a set of non-negative errors. With no values every field is
// 0 and `count` is 0 (an empty evaluation is a value, not an error).
struct ErrorStats {
  size_t count = 0;
  double mean = 0.0;
  // Median of an even count is the mean of the two middle values.
  double median = 0.0;
  // Root mean square: sqrt(sum(e^2) / count).
  double rmse = 0.0;
  double max = 0.0;
};

ErrorStats ComputeErrorStats(std::vector<double> values);

// Share of `values` strictly below `threshold` (the "< t" of Knapitsch et
// al. 2017), weighted by `weights` when given (same length), divided by
// `denominator` (the total weight when negative). Returns 0 when the
// denominator is 0.
double ShareBelow(const std::vector<double>& values, double threshold,
                  const std::vector<double>& weights = {},
                  double denominator = -1.0);

// F-score 2PR/(P+R); 0 when P + R = 0.
double FScore(double precision, double recall);

// True when `thresholds` is non-empty, finite, positive and strictly
// increasing; otherwise LOG(ERROR)s naming `option_name` and returns false.
bool CheckThresholds(const std::vector<double>& thresholds,
                     const std::string& option_name);

}  // namespace colmap_lidar
