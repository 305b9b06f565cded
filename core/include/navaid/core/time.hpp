#pragma once
// Time in navaid: int64 nanoseconds since an arbitrary epoch. Seconds appear only at the edges
// (file formats, human text), and are parsed and printed exactly so that round trips are lossless.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace navaid {

using Timestamp = std::int64_t;  ///< nanoseconds
using Duration = std::int64_t;   ///< nanoseconds

constexpr Duration kNanosecondsPerSecond = 1'000'000'000;

/// Seconds (double) to nanoseconds, rounded to the nearest nanosecond.
Timestamp seconds_to_ns(double seconds);
/// Nanoseconds to seconds as double (lossy beyond ~0.1 us for epoch-sized values).
double ns_to_seconds(Timestamp t);

/// Exact decimal seconds ("1403715273.262142976", "12.5", "-3", "1.4037e+09") to nanoseconds.
/// Plain decimals are converted digit by digit (no floating point); exponent notation goes through
/// long double and is rounded to the nanosecond; fractional digits beyond the ninth are rounded.
/// Returns nullopt on anything else (empty, NaN, Inf, trailing garbage, out of int64 range).
std::optional<Timestamp> parse_seconds(std::string_view text);
/// Integer nanoseconds ("1403715273262142976") to Timestamp; nullopt on anything else.
std::optional<Timestamp> parse_nanoseconds(std::string_view text);

/// Exact decimal seconds with 9 fractional digits ("1403715273.262142976").
std::string format_seconds(Timestamp t);

}  // namespace navaid
