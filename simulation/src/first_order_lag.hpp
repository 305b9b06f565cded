#pragma once
// The bounded first-order lag the simulated person's body and hand move by: the rate of change
// that takes `value` toward `target` with time constant tau, bounded by `bound`, without passing
// the target within dt. A floor of 5 % of the bound ends the exponential approach in finite time
// (a person settles).
#include <algorithm>
#include <cmath>

namespace navaid::simulation {

inline double lag_rate(double value, double target, double tau, double bound, double dt) {
  const double error = target - value;
  const double magnitude = std::max(std::abs(error) / tau, 0.05 * bound);
  double rate = std::clamp(std::copysign(magnitude, error), -bound, bound);
  if (std::abs(rate) * dt >= std::abs(error)) rate = error / dt;
  return rate;
}

}  // namespace navaid::simulation
