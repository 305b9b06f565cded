#pragma once
// Private helpers shared by the nmea_*.cpp files.
#include <cstddef>
#include <map>
#include <string>
#include <string_view>

#include "navaid/io/recording.hpp"

namespace navaid::io::nmea_detail {

/// Counted warnings naming source and line, with a cap per kind: a corrupt capture of a million
/// lines must not produce a million report entries (DataReport merges equal messages only).
class Warnings {
 public:
  Warnings(std::string source, DataReport* report, std::size_t max_listed)
      : source_(std::move(source)), report_(report), max_listed_(max_listed) {}

  void warn(const std::string& kind, std::size_t line, const std::string& detail) {
    if (report_ == nullptr) return;
    std::size_t& n = listed_[kind];
    if (n < max_listed_) {
      ++n;
      report_->warn(source_, (line > 0 ? "line " + std::to_string(line) + ": " : std::string()) + detail);
    } else {
      report_->warn(source_, kind + " (further lines not listed)");
    }
  }
  const std::string& source() const { return source_; }

 private:
  std::string source_;
  DataReport* report_;
  std::size_t max_listed_;
  std::map<std::string, std::size_t> listed_;
};

/// "hh:mm:ss.sss" for messages.
std::string format_time_of_day(long long ns);

}  // namespace navaid::io::nmea_detail
