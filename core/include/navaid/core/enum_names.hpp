#pragma once
// One name table per enum gives both directions (to_string and *_from_string), so the two can
// never disagree. Private to the interaction room.
#include <array>
#include <optional>
#include <string_view>
#include <utility>

namespace navaid::interaction::detail {

template <typename E, std::size_t N>
using NameTable = std::array<std::pair<E, std::string_view>, N>;

template <typename E, std::size_t N>
std::string_view name_of(const NameTable<E, N>& table, E value) {
  for (const auto& [v, name] : table) {
    if (v == value) return name;
  }
  return "unknown";
}

template <typename E, std::size_t N>
std::optional<E> value_of(const NameTable<E, N>& table, std::string_view name) {
  for (const auto& [v, n] : table) {
    if (n == name) return v;
  }
  return std::nullopt;
}

}  // namespace navaid::interaction::detail
