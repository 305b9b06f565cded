#pragma once
// Validation helpers shared by the sensor models' validate() functions: a ConfigError names the
// source, the key, the allowed range with its unit, and the value found.
#include <string>

namespace navaid::simulation::detail {

/// Shortest readable form of a number for messages ("0.5", "1e-06").
std::string format_number(double v);

/// Throws ConfigError unless v is finite and in [lo, hi] (or (lo, hi] when open_lo).
void check_range(const std::string& source, const std::string& key, double v, double lo, double hi,
                 const std::string& unit, bool open_lo = false);

}  // namespace navaid::simulation::detail
