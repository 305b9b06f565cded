#include "navaid/io/recording.hpp"

namespace navaid::io {

void DataReport::warn(const std::string& source, const std::string& message) {
  for (auto& w : warnings) {
    if (w.source == source && w.message == message) {
      ++w.count;
      return;
    }
  }
  warnings.push_back({source, message, 1});
}

std::size_t DataReport::total() const {
  std::size_t n = 0;
  for (const auto& w : warnings) n += w.count;
  return n;
}

}  // namespace navaid::io
