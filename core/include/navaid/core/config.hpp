#pragma once
// YAML configuration with validation and command-line overrides.
//
// Every accessor validates: a missing key, a value of the wrong type or one outside its allowed
// range raises ConfigError naming the file (or the --set override it came from), the dotted key
// and the allowed range. Overrides "a.b.c=value" replace or create keys; the value is parsed as
// YAML, so "--set imu.rate=400", "--set name=head" and "--set list=[1,2,3]" all work.
// reject_unknown_keys(schema) catches typos against the declared keys; reading changes nothing.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace navaid {

class ConfigSchema;  // navaid/core/config_schema.hpp

/// Closed interval [min, max] for numeric keys.
struct Range {
  double min;
  double max;
};

class Config {
 public:
  /// Empty configuration (every get_* with a default returns the default).
  Config();
  ~Config();
  Config(const Config&);
  Config& operator=(const Config&);
  Config(Config&&) noexcept;
  Config& operator=(Config&&) noexcept;

  /// Loads a YAML file; throws ConfigError (key "<file>") when it is missing or not valid YAML.
  static Config load(const std::filesystem::path& file, const std::vector<std::string>& overrides = {});
  /// Parses YAML text; `name` stands for the file in messages.
  static Config parse(const std::string& yaml, const std::string& name = "<config>",
                      const std::vector<std::string>& overrides = {});

  /// Applies "a.b.c=value"; throws ConfigError on a malformed assignment or a path through a scalar.
  void apply_override(const std::string& assignment);

  bool has(std::string_view key) const;
  /// The file name (or "--set key=value") that the key's value came from.
  std::string origin(std::string_view key) const;

  double get_double(std::string_view key, Range allowed) const;
  double get_double(std::string_view key, double fallback, Range allowed) const;
  long long get_int(std::string_view key, long long min, long long max) const;
  long long get_int(std::string_view key, long long fallback, long long min, long long max) const;
  bool get_bool(std::string_view key) const;
  bool get_bool(std::string_view key, bool fallback) const;
  /// `allowed` empty means any string.
  std::string get_string(std::string_view key, const std::vector<std::string>& allowed = {}) const;
  std::string get_string(std::string_view key, const std::string& fallback,
                         const std::vector<std::string>& allowed) const;
  /// A sequence of numbers, each in `allowed`; `size` 0 means any length.
  std::vector<double> get_doubles(std::string_view key, std::size_t size, Range allowed) const;
  /// A list of names; `fallback` when the key is absent.
  std::vector<std::string> get_strings(std::string_view key, const std::vector<std::string>& fallback) const;
  /// Child keys of a map (empty when the key is absent).
  std::vector<std::string> child_keys(std::string_view key) const;

  /// Obsolete (reads are not recorded): throws std::logic_error. Pass the command's schema.
  void reject_unknown_keys() const;
  /// Throws ConfigError naming the first leaf key that `schema` (the command's keys) lacks.
  void reject_unknown_keys(const ConfigSchema& schema) const;

  /// Every leaf key of the loaded tree (dotted, in file order).
  std::vector<std::string> leaf_keys() const;

  /// The given keys as YAML (after overrides).
  std::string dump() const;
  /// Plus each absent key of `schema` with its default (ConfigReads::defaults(): the run's).
  std::string dump(const ConfigSchema& schema) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace navaid
