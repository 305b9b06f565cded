#include "recording_edits.hpp"

#include <sstream>

#include "test_support.hpp"

namespace navaid::testing {

std::vector<std::string> lines_of(const std::filesystem::path& file) {
  std::vector<std::string> lines;
  std::istringstream in(read_text(file));
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

void write_lines(const std::filesystem::path& file, const std::vector<std::string>& lines) {
  std::string text;
  for (const auto& l : lines) text += l + "\n";
  write_text(file, text);
}

void edit_line(const std::filesystem::path& file, std::size_t number, const std::function<void(std::string&)>& edit) {
  auto lines = lines_of(file);
  edit(lines.at(number - 1));
  write_lines(file, lines);
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> f;
  std::stringstream s(line);
  for (std::string x; std::getline(s, x, ',');) f.push_back(x);
  if (!line.empty() && line.back() == ',') f.emplace_back();  // an empty last field
  return f;
}

std::string join_csv(const std::vector<std::string>& fields) {
  std::string out;
  for (std::size_t i = 0; i < fields.size(); ++i) out += (i ? "," : "") + fields[i];
  return out;
}

void edit_rows(const std::filesystem::path& file, long long t0_ns,
               const std::function<bool(std::vector<std::string>& fields, double t_s)>& edit) {
  const auto lines = lines_of(file);
  std::vector<std::string> out{lines.at(0)};
  for (std::size_t i = 1; i < lines.size(); ++i) {
    auto f = split_csv(lines[i]);
    if (edit(f, static_cast<double>(std::stoll(f.at(0)) - t0_ns) * 1e-9)) out.push_back(join_csv(f));
  }
  write_lines(file, out);
}

}  // namespace navaid::testing
