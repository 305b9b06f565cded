#include "navaid/core/number_text.hpp"

#include <sstream>

namespace navaid {

std::string number_text(double v, int significant_digits) {
  std::ostringstream s;
  s.precision(significant_digits);
  s << v;
  return s.str();
}

}  // namespace navaid
