#pragma once
// Sample times of a sensor running at a fixed rate: an integer-nanosecond grid, computed as
// start + round(k * period) so that long recordings do not drift, and shared by every simulated
// sensor so that all of them evaluate the trajectory at exactly their time stamps.
#include <vector>

#include "navaid/core/time.hpp"

namespace navaid::simulation {

/// Times [ns, relative to the trajectory's t = 0] of samples k = 0, 1, ... at rate_hz from t_begin_s
/// up to and including t_end_s (when on the grid). Empty when t_end_s < t_begin_s. rate_hz > 0.
std::vector<Timestamp> time_grid(double t_begin_s, double t_end_s, double rate_hz);

}  // namespace navaid::simulation
