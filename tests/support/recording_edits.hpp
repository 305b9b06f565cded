// Line and field edits of a recording's CSV files: the corrupt-recording and sensor-dropout
// matrices (docs/robustness.md) damage copies of recordings with these.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace navaid::testing {

std::vector<std::string> lines_of(const std::filesystem::path& file);
void write_lines(const std::filesystem::path& file, const std::vector<std::string>& lines);
/// Applies `edit` to line `number` (1-based) of `file`.
void edit_line(const std::filesystem::path& file, std::size_t number, const std::function<void(std::string&)>& edit);

std::vector<std::string> split_csv(const std::string& line);
std::string join_csv(const std::vector<std::string>& fields);

/// Rewrites the data rows of a CSV with a header line: `edit` gets a row's fields and its time
/// in seconds after `t0_ns` (column 0 in ns) and returns false to drop the row.
void edit_rows(const std::filesystem::path& file, long long t0_ns,
               const std::function<bool(std::vector<std::string>& fields, double t_s)>& edit);

}  // namespace navaid::testing
