#pragma once
// Summary statistics of a set of non-negative error magnitudes (metres, degrees, percent).
#include <cstddef>
#include <vector>

namespace navaid::evaluation {

struct ErrorStatistics {
  std::size_t count = 0;
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;  ///< middle value; mean of the two middle values for an even count
  double std = 0.0;     ///< population standard deviation (divides by count, as numpy and rpg do)
  double min = 0.0;
  double max = 0.0;
};

/// Throws navaid::Error on an empty set or a non-finite value.
ErrorStatistics compute_statistics(const std::vector<double>& errors);

}  // namespace navaid::evaluation
