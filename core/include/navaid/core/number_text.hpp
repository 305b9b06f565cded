#pragma once
// A number in an error message or a log line, as std::ostream writes it (shortest of fixed and
// scientific for the precision): the one formatting the messages of every room share.
#include <string>

namespace navaid {

/// `v` with `significant_digits` significant digits (std::ostream's default precision is 6).
std::string number_text(double v, int significant_digits = 6);

}  // namespace navaid
