#pragma once
// One name table per enum gives both directions (to_string and *_from_string), so the two can
// never disagree. A table lists every enumerator once with its one name, next to the enum's
// functions in its .cpp:
//
//   constexpr NameTable<GpsMode, 2> kGpsModeNames{{{GpsMode::kJoint, "joint"}, {GpsMode::kDecoupled, "decoupled"}}};
//   std::string_view to_string(GpsMode m) { return enum_name(kGpsModeNames, m); }
//   std::optional<GpsMode> gps_mode_from_string(std::string_view s) { return enum_value(kGpsModeNames, s); }
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace navaid {

template <typename E, std::size_t N>
using NameTable = std::array<std::pair<E, std::string_view>, N>;

/// The name of value in table; fallback when the table has no entry for it (a value cast from an
/// out-of-range integer).
template <typename E, std::size_t N>
constexpr std::string_view enum_name(const NameTable<E, N>& table, E value, std::string_view fallback = "unknown") {
  for (const auto& [v, name] : table) {
    if (v == value) return name;
  }
  return fallback;
}

/// The value whose name is exactly name (case-sensitive); nullopt for any other name.
template <typename E, std::size_t N>
constexpr std::optional<E> enum_value(const NameTable<E, N>& table, std::string_view name) {
  for (const auto& [v, n] : table) {
    if (n == name) return v;
  }
  return std::nullopt;
}

/// All names of the table in its order, e.g. as the allowed values of a Config key.
template <typename E, std::size_t N>
std::vector<std::string> enum_names(const NameTable<E, N>& table) {
  std::vector<std::string> names;
  names.reserve(N);
  for (const auto& entry : table) names.emplace_back(entry.second);
  return names;
}

}  // namespace navaid
