#include "navaid/simulation/time_grid.hpp"

#include <cmath>
#include <stdexcept>

namespace navaid::simulation {

std::vector<Timestamp> time_grid(double t_begin_s, double t_end_s, double rate_hz) {
  if (!(rate_hz > 0) || !std::isfinite(rate_hz)) throw std::invalid_argument("time_grid: rate must be positive");
  std::vector<Timestamp> times;
  if (!(t_end_s >= t_begin_s)) return times;
  const Timestamp start = seconds_to_ns(t_begin_s);
  const Timestamp end = seconds_to_ns(t_end_s);
  const double period_ns = static_cast<double>(kNanosecondsPerSecond) / rate_hz;
  const auto count = static_cast<std::size_t>(std::floor(static_cast<double>(end - start) / period_ns + 1e-9)) + 1;
  times.reserve(count);
  for (std::size_t k = 0; k < count; ++k) times.push_back(start + std::llround(static_cast<double>(k) * period_ns));
  return times;
}

}  // namespace navaid::simulation
