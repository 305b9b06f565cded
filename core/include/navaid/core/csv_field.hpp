#pragma once
// Free text in the CSV files navaid writes (cue texts, guidance details): one field, quoted only
// when it must be, so that every CSV reader takes it back whole; and splitting such a line.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace navaid {

/// Double-quoted (quotes doubled, line breaks as spaces) when it holds a comma, a quote or a line
/// break; as written otherwise.
std::string csv_field(const std::string& text);

/// The fields of one CSV line as csv_field writes them: a field that starts with a double quote
/// runs to its closing quote ("" inside is a quote). nullopt when a quote is left open.
std::optional<std::vector<std::string>> split_csv_fields(std::string_view line);

}  // namespace navaid
