#include "navaid/evaluation/error_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "navaid/core/errors.hpp"

namespace navaid::evaluation {

ErrorStatistics compute_statistics(const std::vector<double>& errors) {
  if (errors.empty()) throw Error("error statistics of an empty set");
  ErrorStatistics s;
  s.count = errors.size();
  double sum = 0.0, sum_sq = 0.0;
  for (std::size_t i = 0; i < errors.size(); ++i) {
    if (!std::isfinite(errors[i])) throw Error("error statistics: value " + std::to_string(i) + " is not finite");
    sum += errors[i];
    sum_sq += errors[i] * errors[i];
  }
  const double n = static_cast<double>(s.count);
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_sq / n);
  double var = 0.0;
  for (const double e : errors) var += (e - s.mean) * (e - s.mean);
  s.std = std::sqrt(var / n);
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  s.min = sorted.front();
  s.max = sorted.back();
  const std::size_t mid = sorted.size() / 2;
  s.median = sorted.size() % 2 == 1 ? sorted[mid] : 0.5 * (sorted[mid - 1] + sorted[mid]);
  return s;
}

}  // namespace navaid::evaluation
