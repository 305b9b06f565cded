#pragma once
// Line-oriented reading of text data files with exact error locations (file:line) and strict field
// parsing: non-numeric text, NaN and Inf are errors, never silently wrong values.
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/core/time.hpp"

namespace navaid::io {

class TextFile {
 public:
  /// Opens `path`; throws IoError when it does not exist or cannot be read.
  explicit TextFile(const std::filesystem::path& path);

  /// Next line without its line ending ("\n" or "\r\n") and, on line 1, without a UTF-8
  /// byte-order mark; false at end of file.
  bool next(std::string& line);
  std::size_t line_number() const { return line_number_; }
  const std::string& path() const { return path_; }

  /// Throws IoError naming this file and the current line.
  [[noreturn]] void fail(const std::string& message) const;

 private:
  std::string path_;
  std::ifstream stream_;
  std::size_t line_number_ = 0;
};

/// Trims ASCII whitespace at both ends.
std::string_view trim(std::string_view text);
/// True for empty lines and lines whose first non-blank character is '#'.
bool is_blank_or_comment(std::string_view line);
/// `text` for an error message: bytes outside printable ASCII as \xNN, cut after `max_chars`.
std::string printable(std::string_view text, std::size_t max_chars = 80);
/// Splits on `separator` (or on runs of blanks when separator is ' '), trimming each field.
std::vector<std::string_view> split_fields(std::string_view line, char separator);

/// Strict field parsers: on failure they call file.fail() with the column name and the bad text.
double parse_double(const TextFile& file, std::string_view text, std::string_view column);
long long parse_integer(const TextFile& file, std::string_view text, std::string_view column);
Timestamp parse_seconds_field(const TextFile& file, std::string_view text, std::string_view column);
Timestamp parse_nanoseconds_field(const TextFile& file, std::string_view text, std::string_view column);

/// Requires exactly `expected` fields (or at least `expected` when `at_least`).
void require_field_count(const TextFile& file, const std::vector<std::string_view>& fields,
                         std::size_t expected, bool at_least = false);

/// Requires t > previous (strictly increasing); names both timestamps on failure.
void require_increasing(const TextFile& file, Timestamp previous, Timestamp t, bool has_previous);

}  // namespace navaid::io
