#include "value_checks.hpp"

#include <cmath>
#include <sstream>

#include "navaid/core/errors.hpp"

namespace navaid::simulation::detail {

std::string format_number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

void check_range(const std::string& source, const std::string& key, double v, double lo, double hi,
                 const std::string& unit, bool open_lo) {
  const bool lo_ok = open_lo ? v > lo : v >= lo;
  if (!std::isfinite(v) || !lo_ok || v > hi) {
    throw ConfigError(source, key,
                      std::string("expected a value in ") + (open_lo ? "(" : "[") + format_number(lo) + ", " +
                          format_number(hi) + "]" + (unit.empty() ? "" : " " + unit) + ", found " + format_number(v));
  }
}

}  // namespace navaid::simulation::detail
