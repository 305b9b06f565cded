#pragma once
// Free text in the CSV files navaid writes (cue texts, guidance details): one field, quoted only
// when it must be, so that every CSV reader takes it back whole.
#include <string>

namespace navaid {

/// Double-quoted (quotes doubled, line breaks as spaces) when it holds a comma, a quote or a line
/// break; as written otherwise.
std::string csv_field(const std::string& text);

}  // namespace navaid
