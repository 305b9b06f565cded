#include "navaid/core/config_schema.hpp"

#include "navaid/core/config_reads.hpp"

#include <algorithm>
#include <charconv>
#include <map>
#include <sstream>
#include <stdexcept>

namespace navaid {

namespace {

// Formatting shared with the Config getters' messages (config.cpp): the same range text.
std::string format_number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string range_text(Range r) { return "[" + format_number(r.min) + ", " + format_number(r.max) + "]"; }

std::string int_range_text(long long min, long long max) {
  return "[" + std::to_string(min) + ", " + std::to_string(max) + "]";
}

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& i : items) out += (out.empty() ? "" : ", ") + i;
  return out;
}

// The shortest text that reads back as the same double (as dump() writes defaults).
std::string shortest(double v) {
  char buffer[32];
  const auto r = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, r.ptr);
}

// A string as a YAML flow scalar: plain when that reads back as the same string.
std::string yaml_scalar(const std::string& s) {
  const bool plain = !s.empty() && s.find_first_of(":#,[]{}&*!|>'\"%@`\n") == std::string::npos &&
                     s.front() != ' ' && s.back() != ' ' && s.front() != '-' && s.front() != '?';
  if (plain) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace

namespace {

thread_local ConfigReads* current_reads = nullptr;

// Notes the default of an absent key for this thread's ConfigReads (as Config::dump writes them:
// lists of numbers were never written, and are not now).
template <typename Key>
void note_default(const Config& config, const Key& key) {
  if (current_reads != nullptr && key.fallback && !config.has(key.name)) ConfigReads::note(config, describe(key));
}

}  // namespace

ConfigReads::ConfigReads(const Config& config) : config_(&config), outer_(current_reads) { current_reads = this; }
ConfigReads::~ConfigReads() { current_reads = outer_; }

void ConfigReads::note(const Config& config, const ConfigKeyInfo& used) {
  if (current_reads == nullptr || current_reads->config_ != &config || current_reads->defaults_.find(used.name) != nullptr)
    return;
  current_reads->defaults_.add_info(used);
}

double get(const Config& config, const ConfigKey<double>& key) {
  note_default(config, key);
  return key.fallback ? config.get_double(key.name, *key.fallback, key.range) : config.get_double(key.name, key.range);
}

long long get(const Config& config, const ConfigKey<long long>& key) {
  note_default(config, key);
  return key.fallback ? config.get_int(key.name, *key.fallback, key.min, key.max)
                      : config.get_int(key.name, key.min, key.max);
}

int get(const Config& config, const ConfigKey<int>& key) {
  note_default(config, key);
  return static_cast<int>(key.fallback ? config.get_int(key.name, *key.fallback, key.min, key.max)
                                       : config.get_int(key.name, key.min, key.max));
}

bool get(const Config& config, const ConfigKey<bool>& key) {
  note_default(config, key);
  return key.fallback ? config.get_bool(key.name, *key.fallback) : config.get_bool(key.name);
}

std::string get(const Config& config, const ConfigKey<std::string>& key) {
  note_default(config, key);
  return key.fallback ? config.get_string(key.name, *key.fallback, key.allowed) : config.get_string(key.name, key.allowed);
}

std::vector<double> get(const Config& config, const ConfigKey<std::vector<double>>& key) {
  if (key.fallback && !config.has(key.name)) return *key.fallback;
  return config.get_doubles(key.name, key.size, key.range);
}

std::vector<std::string> get(const Config& config, const ConfigKey<std::vector<std::string>>& key) {
  if (current_reads != nullptr && !config.has(key.name)) ConfigReads::note(config, describe(key));
  return config.get_strings(key.name, key.fallback);
}

std::string ConfigKeyInfo::default_text() const {
  if (no_default) return "(none)";
  const bool text = type == "string" || type == "names";
  std::vector<std::string> items;
  for (const auto& d : defaults) items.push_back(text ? yaml_scalar(d) : d);
  if (!list) return items.empty() ? std::string() : items.front();
  return "[" + join(items) + "]";
}

bool ConfigKeyInfo::same_declaration(const ConfigKeyInfo& o) const {
  return name == o.name && type == o.type && no_default == o.no_default && list == o.list && defaults == o.defaults &&
         allowed == o.allowed && is_map == o.is_map;
}

ConfigKeyInfo describe(const ConfigKey<double>& key) {
  ConfigKeyInfo i{key.name, "number", !key.fallback, false, {}, range_text(key.range), key.doc, false};
  if (key.fallback) i.defaults = {shortest(*key.fallback)};
  return i;
}

ConfigKeyInfo describe(const ConfigKey<long long>& key) {
  ConfigKeyInfo i{key.name, "integer", !key.fallback, false, {}, int_range_text(key.min, key.max), key.doc, false};
  if (key.fallback) i.defaults = {std::to_string(*key.fallback)};
  return i;
}

ConfigKeyInfo describe(const ConfigKey<int>& key) {
  ConfigKeyInfo i{key.name, "integer", !key.fallback, false, {}, int_range_text(key.min, key.max), key.doc, false};
  if (key.fallback) i.defaults = {std::to_string(*key.fallback)};
  return i;
}

ConfigKeyInfo describe(const ConfigKey<bool>& key) {
  ConfigKeyInfo i{key.name, "bool", !key.fallback, false, {}, "true or false", key.doc, false};
  if (key.fallback) i.defaults = {*key.fallback ? "true" : "false"};
  return i;
}

ConfigKeyInfo describe(const ConfigKey<std::string>& key) {
  ConfigKeyInfo i{key.name, "string", !key.fallback, false, {}, key.allowed.empty() ? "" : "one of: " + join(key.allowed),
                  key.doc, false};
  if (key.fallback) i.defaults = {*key.fallback};
  return i;
}

ConfigKeyInfo describe(const ConfigKey<std::vector<double>>& key) {
  const std::string what =
      (key.size ? std::to_string(key.size) + " numbers" : std::string("a list of numbers")) + " in " + range_text(key.range);
  ConfigKeyInfo i{key.name, "numbers", !key.fallback, true, {}, what, key.doc, false};
  if (key.fallback)
    for (double v : *key.fallback) i.defaults.push_back(shortest(v));
  return i;
}

ConfigKeyInfo describe(const ConfigKey<std::vector<std::string>>& key) {
  ConfigKeyInfo i{key.name, "names", false, true, {}, "", key.doc, false};
  i.defaults = key.fallback;
  return i;
}

ConfigKeyInfo describe(const ConfigMapKey& key) {
  return ConfigKeyInfo{key.name, "map", false, false, {}, key.entries, key.doc, true};
}

ConfigSchema& ConfigSchema::add_info(const ConfigKeyInfo& info) {
  if (const ConfigKeyInfo* old = find(info.name)) {
    if (!old->same_declaration(info))
      throw std::logic_error("configuration key '" + info.name + "' is declared twice with different type, default or range");
    return *this;
  }
  keys_.push_back(info);
  return *this;
}

ConfigSchema& ConfigSchema::add(const ConfigSchema& other) {
  for (const auto& k : other.keys_) add_info(k);
  return *this;
}

const ConfigKeyInfo* ConfigSchema::find(std::string_view name) const {
  for (const auto& k : keys_)
    if (k.name == name) return &k;
  return nullptr;
}

bool ConfigSchema::declares(std::string_view leaf) const {
  for (const auto& k : keys_) {
    if (k.name == leaf) return true;
    if (k.is_map && leaf.size() > k.name.size() && leaf.substr(0, k.name.size()) == k.name && leaf[k.name.size()] == '.')
      return true;
  }
  return false;
}

std::vector<ConfigKeyInfo> ConfigSchema::listing(std::string_view prefix) const {
  std::vector<ConfigKeyInfo> out;
  for (const auto& k : keys_) {
    const std::string_view n = k.name;
    if (prefix.empty() || n == prefix ||
        (n.size() > prefix.size() && n.substr(0, prefix.size()) == prefix && n[prefix.size()] == '.'))
      out.push_back(k);
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  return out;
}

namespace {

std::string markdown_cell(std::string s) {
  std::string out;
  for (char c : s) {
    if (c == '|') out += '\\';
    out += c;
  }
  return out;
}

}  // namespace

std::string format_schema(const ConfigSchema& schema, std::string_view prefix, bool markdown) {
  auto keys = schema.listing(prefix);
  std::string out;
  if (!markdown) {
    for (const auto& k : keys) {
      out += k.name + "  (" + k.type;
      if (!k.is_map) out += ", default " + k.default_text();
      if (!k.allowed.empty()) out += ", " + k.allowed;
      out += ")\n    " + k.doc + "\n";
    }
    return out;
  }
  // Keys without a dot first (one table), then a table per top-level section.
  std::stable_partition(keys.begin(), keys.end(),
                        [](const ConfigKeyInfo& k) { return k.name.find('.') == std::string::npos; });
  std::string section = "\n";  // no section yet
  for (const auto& k : keys) {
    const std::size_t dot = k.name.find('.');
    const std::string top = dot == std::string::npos ? std::string("top level") : k.name.substr(0, dot);
    if (top != section) {
      section = top;
      out += "\n## " + section + "\n\n| key | type | default | allowed | description |\n|---|---|---|---|---|\n";
    }
    out += "| `" + k.name + (k.is_map ? ".*" : "") + "` | " + k.type + " | " +
           (k.is_map ? std::string() : "`" + markdown_cell(k.default_text()) + "`") + " | " + markdown_cell(k.allowed) +
           " | " + markdown_cell(k.doc) + " |\n";
  }
  return out;
}

}  // namespace navaid
