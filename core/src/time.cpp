#include "navaid/core/time.hpp"

#include <cmath>
#include <cstdlib>
#include <limits>

namespace navaid {

Timestamp seconds_to_ns(double seconds) {
  return static_cast<Timestamp>(std::llround(seconds * 1e9));
}

double ns_to_seconds(Timestamp t) { return static_cast<double>(t) * 1e-9; }

std::optional<Timestamp> parse_nanoseconds(std::string_view text) {
  if (text.empty()) return std::nullopt;
  std::size_t i = 0;
  bool negative = false;
  if (text[0] == '-' || text[0] == '+') {
    negative = text[0] == '-';
    i = 1;
  }
  if (i == text.size()) return std::nullopt;
  constexpr auto kMax = std::numeric_limits<std::int64_t>::max();
  std::int64_t value = 0;
  for (; i < text.size(); ++i) {
    const char c = text[i];
    if (c < '0' || c > '9') return std::nullopt;
    const int digit = c - '0';
    if (value > (kMax - digit) / 10) return std::nullopt;
    value = value * 10 + digit;
  }
  return negative ? -value : value;
}

namespace {

// Exponent notation (e.g. "1.403715524907143116e+09") cannot be converted digit by digit without
// a big-number routine; long double keeps 64 mantissa bits, enough for nanoseconds up to ~2^63.
std::optional<Timestamp> parse_scientific(std::string_view text) {
  const std::string buffer(text);
  char* end = nullptr;
  const long double value = std::strtold(buffer.c_str(), &end);
  if (end != buffer.c_str() + buffer.size() || !std::isfinite(value)) return std::nullopt;
  const long double ns = value * 1e9L;
  if (std::fabs(ns) >= 9.2e18L) return std::nullopt;
  return static_cast<Timestamp>(std::llround(ns));
}

}  // namespace

std::optional<Timestamp> parse_seconds(std::string_view text) {
  if (text.empty()) return std::nullopt;
  if (text.find_first_of("eE") != std::string_view::npos) return parse_scientific(text);
  bool negative = false;
  std::size_t i = 0;
  if (text[0] == '-' || text[0] == '+') {
    negative = text[0] == '-';
    i = 1;
  }
  const std::size_t dot = text.find('.', i);
  const std::string_view whole = text.substr(i, dot == std::string_view::npos ? std::string_view::npos : dot - i);
  std::string_view frac = dot == std::string_view::npos ? std::string_view{} : text.substr(dot + 1);
  if (whole.empty() && frac.empty()) return std::nullopt;
  std::int64_t seconds = 0;
  if (!whole.empty()) {
    const auto s = parse_nanoseconds(whole);
    if (!s || whole[0] == '-' || whole[0] == '+') return std::nullopt;
    if (*s > std::numeric_limits<std::int64_t>::max() / kNanosecondsPerSecond - 1) return std::nullopt;
    seconds = *s;
  }
  std::int64_t nanos = 0;
  int digits = 0;
  bool round_up = false;
  for (std::size_t k = 0; k < frac.size(); ++k) {
    const char c = frac[k];
    if (c < '0' || c > '9') return std::nullopt;
    if (digits < 9) {
      nanos = nanos * 10 + (c - '0');
      ++digits;
    } else if (k == 9) {
      round_up = c >= '5';
    }
  }
  for (; digits < 9; ++digits) nanos *= 10;
  std::int64_t total = seconds * kNanosecondsPerSecond + nanos + (round_up ? 1 : 0);
  return negative ? -total : total;
}

std::string format_seconds(Timestamp t) {
  const bool negative = t < 0;
  // Work in unsigned to cover INT64_MIN.
  const auto magnitude = negative ? static_cast<std::uint64_t>(-(t + 1)) + 1 : static_cast<std::uint64_t>(t);
  std::string frac = std::to_string(magnitude % 1'000'000'000ULL);
  frac.insert(0, 9 - frac.size(), '0');
  return (negative ? "-" : "") + std::to_string(magnitude / 1'000'000'000ULL) + "." + frac;
}

}  // namespace navaid
