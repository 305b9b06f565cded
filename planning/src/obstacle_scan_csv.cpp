#include "navaid/planning/obstacle_scan_csv.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <optional>
#include <string_view>

#include <fmt/format.h>

#include "navaid/core/errors.hpp"
#include "navaid/planning/angles.hpp"

namespace navaid::planning {

namespace {

constexpr std::string_view kFixedColumns[] = {"t_ns", "ground", "ransac", "obstacle_points", "drop_off_points"};
constexpr std::size_t kFixed = std::size(kFixedColumns);

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      fields.push_back(line.substr(start));
      return fields;
    }
    fields.push_back(line.substr(start, comma - start));
    start = comma + 1;
  }
}

template <class T>
std::optional<T> parse_whole(std::string_view text) {
  T value{};
  if (text.empty()) return std::nullopt;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

std::string shown(std::string_view text) { return fmt::format("'{}'", text.substr(0, 40)); }

}  // namespace

std::vector<mapping::ObstacleScan> parse_obstacle_scan_csv(std::istream& in, const std::string& name) {
  std::string line;
  std::size_t line_no = 1;
  if (!std::getline(in, line)) throw IoError(name, "empty file: expected the obstacle_scan.csv header");
  if (!line.empty() && line.back() == '\r') line.pop_back();
  std::vector<std::string> header;  // owned: `line` is reused for the rows
  for (const std::string_view h : split(line)) header.emplace_back(h);
  const std::string expected = "t_ns,ground,ransac,obstacle_points,drop_off_points,r_<deg>,...[,d_<deg>,...]";
  if (header.size() <= kFixed) {
    throw IoError(name, line_no, fmt::format("not an obstacle_scan.csv header (expected {}; got {} columns)", expected,
                                             header.size()));
  }
  for (std::size_t i = 0; i < kFixed; ++i) {
    if (header[i] != kFixedColumns[i]) {
      throw IoError(name, line_no, fmt::format("column {} is {}, expected '{}' (header {})", i + 1, shown(header[i]),
                                               kFixedColumns[i], expected));
    }
  }
  // r_<deg> per bin, then (files since drop-offs are written) as many d_<deg> with the same labels.
  std::size_t r_end = kFixed;
  while (r_end < header.size() && header[r_end].rfind("d_", 0) != 0) ++r_end;
  std::vector<double> label_deg;
  for (std::size_t i = kFixed; i < r_end; ++i) {
    const std::string_view h = header[i];
    const std::optional<double> deg = h.substr(0, 2) == "r_" ? parse_whole<double>(h.substr(2)) : std::nullopt;
    if (!deg || !std::isfinite(*deg)) {
      throw IoError(name, line_no, fmt::format("column {} is {}, expected a bin 'r_<bearing deg>'", i + 1, shown(h)));
    }
    label_deg.push_back(*deg);
  }
  if (label_deg.empty()) {
    throw IoError(name, line_no, fmt::format("no r_<deg> bin columns before the drop-off columns (header {})", expected));
  }
  const std::size_t bins = label_deg.size();
  const bool has_drop_offs = r_end < header.size();
  if (has_drop_offs) {
    if (header.size() - r_end != bins) {
      throw IoError(name, line_no, fmt::format("{} drop-off columns d_<deg> for {} range columns r_<deg>",
                                               header.size() - r_end, bins));
    }
    for (std::size_t b = 0; b < bins; ++b) {
      const std::string_view h = header[r_end + b];
      const std::optional<double> deg = parse_whole<double>(h.substr(2));
      if (!deg || std::abs(*deg - label_deg[b]) > 1e-9) {
        throw IoError(name, line_no, fmt::format("column {} is {}, expected 'd_{}' (the drop-off of bin {})",
                                                 r_end + b + 1, shown(h), header[kFixed + b].substr(2), b));
      }
    }
  }
  const double first = label_deg.front();
  const double increment_deg = bins > 1 ? (label_deg.back() - first) / static_cast<double>(bins - 1) : 1.0;
  if (!(increment_deg > 0.0)) {
    throw IoError(name, line_no, fmt::format("bin labels r_{} .. r_{} do not increase", first, label_deg.back()));
  }
  for (std::size_t b = 0; b < bins; ++b) {
    const double centre = first + static_cast<double>(b) * increment_deg;
    if (std::abs(label_deg[b] - centre) > 0.5 + 1e-9) {
      throw IoError(name, line_no,
                    fmt::format("bin label r_{} (column {}) is not evenly spaced: bin {} should be at {:.2f} deg",
                                label_deg[b], kFixed + b + 1, b, centre));
    }
  }

  std::vector<mapping::ObstacleScan> scans;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::vector<std::string_view> f = split(line);
    if (f.size() != header.size()) {
      throw IoError(name, line_no, fmt::format("{} columns, the header has {}", f.size(), header.size()));
    }
    const auto bad = [&](std::size_t column, const char* what) {
      return IoError(name, line_no,
                     fmt::format("column {} ({}) is {}: expected {}", column + 1, header[column], shown(f[column]), what));
    };
    mapping::ObstacleScan scan =
        mapping::ObstacleScan::empty(bins, deg_to_rad(first), deg_to_rad(increment_deg));
    const auto t = parse_whole<std::int64_t>(f[0]);
    if (!t) throw bad(0, "integer nanoseconds");
    if (!scans.empty() && *t <= scans.back().t) {
      throw IoError(name, line_no,
                    fmt::format("time {} ns does not increase (previous row {} ns)", *t, scans.back().t));
    }
    scan.t = *t;
    const auto ground = parse_whole<int>(f[1]);
    if (!ground || *ground < 0 || *ground > 3) throw bad(1, "a ground source 0..3");
    scan.counters.ground_source = static_cast<mapping::GroundSource>(*ground);
    scan.counters.running_average_used = scan.counters.ground_source != mapping::GroundSource::kPrior;
    const auto ransac = parse_whole<int>(f[2]);
    if (!ransac || (*ransac != 0 && *ransac != 1)) throw bad(2, "0 or 1");
    scan.counters.ransac_succeeded = *ransac == 1;
    const auto obstacles = parse_whole<std::size_t>(f[3]);
    if (!obstacles) throw bad(3, "a point count");
    scan.counters.obstacle_points = *obstacles;
    const auto drop_offs = parse_whole<std::size_t>(f[4]);
    if (!drop_offs) throw bad(4, "a point count");
    scan.counters.drop_off_points = *drop_offs;
    for (std::size_t b = 0; b < bins; ++b) {
      const std::string_view field = f[kFixed + b];
      if (field.empty()) continue;  // nothing in this bin
      const auto r = parse_whole<float>(field);
      if (!r || !std::isfinite(*r) || *r < 0.0f) throw bad(kFixed + b, "a range >= 0 m or empty");
      scan.ranges[b] = *r;
    }
    for (std::size_t b = 0; has_drop_offs && b < bins; ++b) {
      const std::string_view field = f[r_end + b];
      if (field.empty()) continue;  // no drop-off in this bin
      const auto r = parse_whole<float>(field);
      if (!r || !std::isfinite(*r) || *r < 0.0f) throw bad(r_end + b, "a drop-off range >= 0 m or empty");
      scan.drop_off_ranges[b] = *r;
    }
    scans.push_back(std::move(scan));
  }
  if (in.bad()) throw IoError(name, line_no, "read error");
  return scans;
}

std::vector<mapping::ObstacleScan> read_obstacle_scan_csv(const std::filesystem::path& file) {
  if (std::filesystem::is_directory(file)) throw IoError(file.string(), "is a folder, expected obstacle_scan.csv");
  std::ifstream in(file);
  if (!in) throw IoError(file.string(), "cannot open");
  return parse_obstacle_scan_csv(in, file.string());
}

}  // namespace navaid::planning
