#pragma once
// Configuration keys declared once: name, type, default, allowed range or choices, one-line doc.
//
// A module declares each key it reads as a ConfigKey beside the options struct it fills, reads it
// with get(config, key) (which validates exactly as the Config getters do and raises the same
// ConfigError naming the file, the key and the range) and lists its keys in a ConfigSchema.
// `navaid config --list` prints the union of the modules' schemas; docs/config-reference.md is
// generated from it.
//
//   const ConfigKey<double> kUnknownCost{"mapping.cost.unknown_cost", CostMapConfig{}.unknown_cost,
//                                        {0.0, 1.0}, "traversal cost of a cell never observed"};
//   c.unknown_cost = get(config, kUnknownCost);
//
// A key without a default (std::nullopt) is required, or means "off" when absent (its reader checks
// has() first). A ConfigMapKey declares a map whose child names are free (a per-class table):
// every leaf under it is known, its reader validates them.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "navaid/core/config.hpp"

namespace navaid {

template <typename T>
struct ConfigKey;

template <>
struct ConfigKey<double> {
  std::string name;
  std::optional<double> fallback;
  Range range;
  std::string doc;
};

template <>
struct ConfigKey<long long> {
  std::string name;
  std::optional<long long> fallback;
  long long min;
  long long max;
  std::string doc;
};

template <>
struct ConfigKey<int> {
  std::string name;
  std::optional<int> fallback;
  int min;
  int max;
  std::string doc;
};

template <>
struct ConfigKey<bool> {
  std::string name;
  std::optional<bool> fallback;
  std::string doc;
};

template <>
struct ConfigKey<std::string> {
  std::string name;
  std::optional<std::string> fallback;
  std::vector<std::string> allowed;  ///< empty: any string
  std::string doc;
};

/// A list of numbers, each in `range`; `size` 0 means any length.
template <>
struct ConfigKey<std::vector<double>> {
  std::string name;
  std::optional<std::vector<double>> fallback;
  std::size_t size;
  Range range;
  std::string doc;
};

/// A list of names (always optional: the fallback is used when the key is absent).
template <>
struct ConfigKey<std::vector<std::string>> {
  std::string name;
  std::vector<std::string> fallback;
  std::string doc;
};

/// A map whose child names are free (e.g. one entry per semantic class); `entries` says what an
/// entry holds ("probability in [0, 1] per semantic class").
struct ConfigMapKey {
  std::string name;
  std::string entries;
  std::string doc;
};

/// `key` with its range narrowed at read time, for a bound that depends on another key (the
/// declared range stays the widest one).
inline ConfigKey<double> within(ConfigKey<double> key, Range range) {
  key.range = range;
  return key;
}

/// `key` with a default decided at read time (a sensor preset's, a scenario's): such a key is
/// declared without one, and its doc says where the default comes from.
template <typename T>
ConfigKey<T> defaulting_to(ConfigKey<T> key, T fallback) {
  key.fallback = std::move(fallback);
  return key;
}

double get(const Config& config, const ConfigKey<double>& key);
long long get(const Config& config, const ConfigKey<long long>& key);
int get(const Config& config, const ConfigKey<int>& key);
bool get(const Config& config, const ConfigKey<bool>& key);
std::string get(const Config& config, const ConfigKey<std::string>& key);
std::vector<double> get(const Config& config, const ConfigKey<std::vector<double>>& key);
std::vector<std::string> get(const Config& config, const ConfigKey<std::vector<std::string>>& key);

/// One declared key, whatever its type: what listings, reference docs, dump() and the unknown-key
/// check need.
struct ConfigKeyInfo {
  std::string name;
  std::string type;     ///< "number", "integer", "bool", "string", "numbers", "names", "map"
  bool no_default = false;  ///< no default: absent means off, or the reader requires it
  bool list = false;    ///< the default is a list (defaults holds its items)
  std::vector<std::string> defaults;  ///< the default's scalar (one item) or list items, unquoted
  std::string allowed;  ///< "[0, 1]", "one of: a, b", "3 numbers in [-2, 2]", ... (empty: any)
  std::string doc;
  bool is_map = false;  ///< children are free: every leaf under `name` is declared

  /// The default as it is written in YAML ("0.5", "[1, 2]", "\"\""), or "(none)".
  std::string default_text() const;
  /// Same name, type, default and allowed values (the doc may differ).
  bool same_declaration(const ConfigKeyInfo& o) const;
};

ConfigKeyInfo describe(const ConfigKey<double>& key);
ConfigKeyInfo describe(const ConfigKey<long long>& key);
ConfigKeyInfo describe(const ConfigKey<int>& key);
ConfigKeyInfo describe(const ConfigKey<bool>& key);
ConfigKeyInfo describe(const ConfigKey<std::string>& key);
ConfigKeyInfo describe(const ConfigKey<std::vector<double>>& key);
ConfigKeyInfo describe(const ConfigKey<std::vector<std::string>>& key);
ConfigKeyInfo describe(const ConfigMapKey& key);

/// An ordered set of declared keys. Adding a key twice is allowed only when both declarations
/// agree on type, default and allowed values (a std::logic_error names the key otherwise; the
/// first doc is kept), so two modules that read one key cannot disagree on its default or range.
class ConfigSchema {
 public:
  ConfigSchema() = default;

  template <typename Key>
  ConfigSchema& add(const Key& key) {
    return add_info(describe(key));
  }
  ConfigSchema& add(const ConfigSchema& other);
  ConfigSchema& add_info(const ConfigKeyInfo& info);

  const std::vector<ConfigKeyInfo>& keys() const { return keys_; }
  /// The declaration named exactly `name`, or nullptr.
  const ConfigKeyInfo* find(std::string_view name) const;
  /// True when `leaf` is a declared key or lies under a declared map key.
  bool declares(std::string_view leaf) const;
  /// Keys whose name is `prefix` or starts with `prefix` + "." (all keys for an empty prefix),
  /// sorted by name.
  std::vector<ConfigKeyInfo> listing(std::string_view prefix = {}) const;

 private:
  std::vector<ConfigKeyInfo> keys_;
};

/// The listing as plain text (one block per key) or as a Markdown reference (a table per
/// top-level section).
std::string format_schema(const ConfigSchema& schema, std::string_view prefix, bool markdown);

}  // namespace navaid
