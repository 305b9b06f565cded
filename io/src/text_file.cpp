#include "navaid/io/text_file.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace navaid::io {

TextFile::TextFile(const std::filesystem::path& path) : path_(path.string()) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw IoError(path_, "file does not exist");
  if (std::filesystem::is_directory(path, ec)) throw IoError(path_, "is a directory, expected a file");
  stream_.open(path, std::ios::binary);
  if (!stream_) throw IoError(path_, "cannot open for reading");
}

bool TextFile::next(std::string& line) {
  if (!std::getline(stream_, line)) {
    if (stream_.bad()) throw IoError(path_, line_number_ + 1, "read error");
    return false;
  }
  ++line_number_;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  // Spreadsheet exports start UTF-8 files with a byte-order mark; it is not part of the header.
  if (line_number_ == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
  return true;
}

void TextFile::fail(const std::string& message) const { throw IoError(path_, line_number_, message); }

std::string_view trim(std::string_view text) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  while (!text.empty() && blank(text.front())) text.remove_prefix(1);
  while (!text.empty() && blank(text.back())) text.remove_suffix(1);
  return text;
}

std::string printable(std::string_view text, std::size_t max_chars) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  for (const char ch : text) {
    if (out.size() >= max_chars) return out + "...";
    const auto c = static_cast<unsigned char>(ch);
    if (c >= 0x20 && c < 0x7f) {
      out += ch;
    } else {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

bool is_blank_or_comment(std::string_view line) {
  const auto t = trim(line);
  return t.empty() || t.front() == '#';
}

std::vector<std::string_view> split_fields(std::string_view line, char separator) {
  std::vector<std::string_view> fields;
  line = trim(line);
  if (separator == ' ') {
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      std::size_t j = i;
      while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
      if (j > i) fields.push_back(line.substr(i, j - i));
      i = j;
    }
    return fields;
  }
  std::size_t start = 0;
  while (true) {
    const std::size_t end = line.find(separator, start);
    fields.push_back(trim(line.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start)));
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  return fields;
}

namespace {
std::string in_quotes(std::string_view text) { return "'" + std::string(text) + "'"; }
}  // namespace

double parse_double(const TextFile& file, std::string_view text, std::string_view column) {
  const std::string buffer(trim(text));
  if (buffer.empty()) file.fail("column '" + std::string(column) + "' is empty");
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(buffer.c_str(), &end);
  if (end != buffer.c_str() + buffer.size())
    file.fail("column '" + std::string(column) + "': " + in_quotes(buffer) + " is not a number");
  if (!std::isfinite(value) || errno == ERANGE)
    file.fail("column '" + std::string(column) + "': " + in_quotes(buffer) + " is not a finite number");
  return value;
}

long long parse_integer(const TextFile& file, std::string_view text, std::string_view column) {
  const std::string buffer(trim(text));
  char* end = nullptr;
  errno = 0;
  const long long value = std::strtoll(buffer.c_str(), &end, 10);
  if (buffer.empty() || end != buffer.c_str() + buffer.size() || errno == ERANGE)
    file.fail("column '" + std::string(column) + "': " + in_quotes(buffer) + " is not an integer");
  return value;
}

Timestamp parse_seconds_field(const TextFile& file, std::string_view text, std::string_view column) {
  const auto t = parse_seconds(trim(text));
  if (!t) file.fail("column '" + std::string(column) + "': " + in_quotes(trim(text)) + " is not a time in seconds");
  return *t;
}

Timestamp parse_nanoseconds_field(const TextFile& file, std::string_view text, std::string_view column) {
  const auto t = parse_nanoseconds(trim(text));
  if (!t) file.fail("column '" + std::string(column) + "': " + in_quotes(trim(text)) + " is not an integer time in nanoseconds");
  return *t;
}

void require_field_count(const TextFile& file, const std::vector<std::string_view>& fields,
                         std::size_t expected, bool at_least) {
  const bool ok = at_least ? fields.size() >= expected : fields.size() == expected;
  if (!ok)
    file.fail("expected " + std::string(at_least ? "at least " : "") + std::to_string(expected) +
              " fields, found " + std::to_string(fields.size()) + " (truncated or malformed line?)");
}

void require_increasing(const TextFile& file, Timestamp previous, Timestamp t, bool has_previous) {
  if (!has_previous || t > previous) return;
  file.fail(std::string(t == previous ? "duplicate" : "decreasing") + " timestamp " + format_seconds(t) +
            " s (previous line had " + format_seconds(previous) + " s)");
}

}  // namespace navaid::io
