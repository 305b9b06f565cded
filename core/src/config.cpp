#include "navaid/core/config.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "navaid/core/config_schema.hpp"
#include "navaid/core/errors.hpp"

namespace navaid {

struct Config::Impl {
  YAML::Node root = YAML::Node(YAML::NodeType::Map);
  std::string file = "<config>";
  std::map<std::string, std::string> override_origin;  // key -> "--set key=value"
  // Reading changes nothing of ours, but yaml-cpp's const reads are not thread-safe (size() and
  // iteration of a map tidy a list inside the node): every public member takes this lock, so one
  // Config can be read from several threads at once.
  mutable std::recursive_mutex mutex;

  Impl() = default;
  Impl(const Impl& o) : root(YAML::Clone(o.root)), file(o.file), override_origin(o.override_origin) {}
};

using Lock = std::lock_guard<std::recursive_mutex>;

namespace {

std::vector<std::string> split_key(std::string_view key) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (start <= key.size()) {
    const std::size_t dot = key.find('.', start);
    const std::size_t end = dot == std::string_view::npos ? key.size() : dot;
    parts.emplace_back(key.substr(start, end - start));
    if (dot == std::string_view::npos) break;
    start = dot + 1;
  }
  return parts;
}

// Reads go through const nodes (a non-const operator[] would insert the key) and rebind with
// reset(): assigning one yaml-cpp node to another overwrites the referenced content instead.
std::optional<YAML::Node> find(const YAML::Node& root, std::string_view key) {
  YAML::Node node;
  node.reset(root);
  for (const auto& part : split_key(key)) {
    if (!node.IsMap()) return std::nullopt;
    const YAML::Node& parent = node;
    const YAML::Node child = parent[part];
    if (!child.IsDefined() || child.IsNull()) return std::nullopt;
    node.reset(child);
  }
  return node;
}

std::string format_number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string range_text(Range r) { return "[" + format_number(r.min) + ", " + format_number(r.max) + "]"; }

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& i : items) out += (out.empty() ? "" : ", ") + i;
  return out;
}

// Keys name settings: a list or map used as a key ("{}: 1", "[a]: 1") is an error at load time.
void require_name_keys(const YAML::Node& node, const std::string& prefix, const std::string& origin) {
  if (node.IsMap()) {
    for (const auto& kv : node) {
      if (!kv.first.IsScalar())
        throw ConfigError(origin, prefix.empty() ? "<root>" : prefix,
                          "a key must be a name, found a list or map (line " + std::to_string(kv.first.Mark().line + 1) +
                              ")");
      const std::string name = kv.first.Scalar();
      require_name_keys(kv.second, prefix.empty() ? name : prefix + "." + name, origin);
    }
  } else if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) require_name_keys(node[i], prefix + "[" + std::to_string(i) + "]", origin);
  }
}

void collect_leaves(const YAML::Node& node, const std::string& prefix, std::vector<std::string>& out) {
  if (node.IsMap()) {
    for (const auto& kv : node) {
      const std::string key = prefix.empty() ? kv.first.as<std::string>() : prefix + "." + kv.first.as<std::string>();
      collect_leaves(kv.second, key, out);
    }
  } else if (!prefix.empty()) {
    out.push_back(prefix);
  }
}

// Sets `key` in `root` unless a value is in the way (a default never replaces a given value).
void insert_default(YAML::Node& root, const std::string& key, const YAML::Node& value) {
  const auto parts = split_key(key);
  YAML::Node node;
  node.reset(root);
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node child = node[parts[i]];
    if (child.IsDefined() && !child.IsNull() && !child.IsMap()) return;
    if (!child.IsDefined() || child.IsNull()) node[parts[i]] = YAML::Node(YAML::NodeType::Map);
    YAML::Node next = node[parts[i]];
    node.reset(next);
  }
  YAML::Node leaf = node[parts.back()];
  if (!leaf.IsDefined() || leaf.IsNull()) node[parts.back()] = value;
}

}  // namespace

Config::Config() : impl_(std::make_unique<Impl>()) {}
Config::~Config() = default;
Config::Config(const Config& o) {
  const Lock lock(o.impl_->mutex);
  impl_ = std::make_unique<Impl>(*o.impl_);
}
Config& Config::operator=(const Config& o) {
  if (this != &o) *this = Config(o);
  return *this;
}
Config::Config(Config&&) noexcept = default;
Config& Config::operator=(Config&&) noexcept = default;

Config Config::parse(const std::string& yaml, const std::string& name, const std::vector<std::string>& overrides) {
  Config c;
  c.impl_->file = name;
  try {
    YAML::Node root = YAML::Load(yaml);
    if (root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
    if (!root.IsMap()) throw ConfigError(name, "<root>", "the top level must be a map of keys");
    require_name_keys(root, "", name);
    c.impl_->root = root;
  } catch (const YAML::Exception& e) {
    throw ConfigError(name, "<file>", "not valid YAML (line " + std::to_string(e.mark.line + 1) + "): " + e.msg);
  }
  for (const auto& o : overrides) c.apply_override(o);
  return c;
}

Config Config::load(const std::filesystem::path& file, const std::vector<std::string>& overrides) {
  std::ifstream in(file);
  if (!in) throw ConfigError(file.string(), "<file>", "cannot open the configuration file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse(buffer.str(), file.string(), overrides);
}

void Config::apply_override(const std::string& assignment) {
  const Lock lock(impl_->mutex);
  const std::string origin = "--set " + assignment;
  const std::size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw ConfigError(origin, assignment, "an override must look like key.sub.key=value");
  const std::string key = assignment.substr(0, eq);
  const std::string value = assignment.substr(eq + 1);
  const auto parts = split_key(key);
  for (const auto& p : parts)
    if (p.empty()) throw ConfigError(origin, key, "empty path component in the key");
  YAML::Node parsed;
  try {
    parsed = YAML::Load(value);
  } catch (const YAML::Exception& e) {
    throw ConfigError(origin, key, "value is not valid YAML: " + e.msg);
  }
  require_name_keys(parsed, key, origin);
  // Walk down, creating maps; a scalar in the way is an error, not silently replaced.
  std::vector<YAML::Node> chain{impl_->root};
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node child = chain.back()[parts[i]];
    if (child.IsDefined() && !child.IsNull() && !child.IsMap())
      throw ConfigError(origin, key, "'" + parts[i] + "' holds a value, not a map of keys");
    if (!child.IsDefined() || child.IsNull()) {
      chain.back()[parts[i]] = YAML::Node(YAML::NodeType::Map);
      child = chain.back()[parts[i]];
    }
    chain.push_back(child);
  }
  chain.back()[parts.back()] = parsed;
  impl_->override_origin[key] = origin;
}

bool Config::has(std::string_view key) const {
  const Lock lock(impl_->mutex);
  return find(impl_->root, key).has_value();
}

std::string Config::origin(std::string_view key) const {
  const Lock lock(impl_->mutex);
  // An override of a parent map also covers its children.
  std::string k(key.substr(0, key.find('[')));  // list elements come from their list's origin
  while (true) {
    const auto it = impl_->override_origin.find(k);
    if (it != impl_->override_origin.end()) return it->second;
    const std::size_t dot = k.rfind('.');
    if (dot == std::string::npos) return impl_->file;
    k.resize(dot);
  }
}

namespace {

template <typename T>
T scalar_as(const Config& c, const YAML::Node& node, std::string_view key, const char* type_name) {
  if (!node.IsScalar()) throw ConfigError(c.origin(key), std::string(key), std::string("expected ") + type_name + ", found a " + (node.IsMap() ? "map" : "list"));
  try {
    return node.as<T>();
  } catch (const YAML::Exception&) {
    throw ConfigError(c.origin(key), std::string(key), "'" + node.Scalar() + "' is not " + type_name);
  }
}

double checked_double(const Config& c, const YAML::Node& node, std::string_view key, Range allowed) {
  const double v = scalar_as<double>(c, node, key, "a number");
  if (!std::isfinite(v))
    throw ConfigError(c.origin(key), std::string(key), "'" + node.Scalar() + "' is not a finite number; allowed range " + range_text(allowed));
  if (v < allowed.min || v > allowed.max)
    throw ConfigError(c.origin(key), std::string(key), "value " + node.Scalar() + " is outside the allowed range " + range_text(allowed));
  return v;
}

}  // namespace

double Config::get_double(std::string_view key, Range allowed) const {
  const Lock lock(impl_->mutex);
  const auto node = find(impl_->root, key);
  if (!node) throw ConfigError(origin(key), std::string(key), "missing; expected a number in " + range_text(allowed));
  return checked_double(*this, *node, key, allowed);
}

double Config::get_double(std::string_view key, double fallback, Range allowed) const {
  const Lock lock(impl_->mutex);
  return has(key) ? get_double(key, allowed) : fallback;
}

long long Config::get_int(std::string_view key, long long min, long long max) const {
  const Lock lock(impl_->mutex);
  const auto node = find(impl_->root, key);
  const std::string allowed = "[" + std::to_string(min) + ", " + std::to_string(max) + "]";
  if (!node) throw ConfigError(origin(key), std::string(key), "missing; expected an integer in " + allowed);
  const auto v = scalar_as<long long>(*this, *node, key, "an integer");
  if (v < min || v > max)
    throw ConfigError(origin(key), std::string(key), "value " + node->Scalar() + " is outside the allowed range " + allowed);
  return v;
}

long long Config::get_int(std::string_view key, long long fallback, long long min, long long max) const {
  const Lock lock(impl_->mutex);
  return has(key) ? get_int(key, min, max) : fallback;
}

bool Config::get_bool(std::string_view key) const {
  const Lock lock(impl_->mutex);
  const auto node = find(impl_->root, key);
  if (!node) throw ConfigError(origin(key), std::string(key), "missing; expected true or false");
  return scalar_as<bool>(*this, *node, key, "true or false");
}

bool Config::get_bool(std::string_view key, bool fallback) const {
  const Lock lock(impl_->mutex);
  return has(key) ? get_bool(key) : fallback;
}

std::string Config::get_string(std::string_view key, const std::vector<std::string>& allowed) const {
  const Lock lock(impl_->mutex);
  const auto node = find(impl_->root, key);
  const std::string allowed_text = allowed.empty() ? "a string" : "one of: " + join(allowed);
  if (!node) throw ConfigError(origin(key), std::string(key), "missing; expected " + allowed_text);
  const auto v = scalar_as<std::string>(*this, *node, key, "a string");
  if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), v) == allowed.end())
    throw ConfigError(origin(key), std::string(key), "'" + v + "' is not allowed; expected " + allowed_text);
  return v;
}

std::string Config::get_string(std::string_view key, const std::string& fallback,
                               const std::vector<std::string>& allowed) const {
  const Lock lock(impl_->mutex);
  return has(key) ? get_string(key, allowed) : fallback;
}

std::vector<double> Config::get_doubles(std::string_view key, std::size_t size, Range allowed) const {
  const Lock lock(impl_->mutex);
  const auto node = find(impl_->root, key);
  const std::string what = (size ? std::to_string(size) + " numbers" : std::string("a list of numbers")) + " in " + range_text(allowed);
  if (!node) throw ConfigError(origin(key), std::string(key), "missing; expected " + what);
  if (!node->IsSequence()) throw ConfigError(origin(key), std::string(key), "expected " + what + ", found a single value or map");
  if (size && node->size() != size)
    throw ConfigError(origin(key), std::string(key), "expected " + what + ", found " + std::to_string(node->size()) + " values");
  std::vector<double> out;
  for (std::size_t i = 0; i < node->size(); ++i)
    out.push_back(checked_double(*this, (*node)[i], std::string(key) + "[" + std::to_string(i) + "]", allowed));
  return out;
}

std::vector<std::string> Config::get_strings(std::string_view key, const std::vector<std::string>& fallback) const {
  const Lock lock(impl_->mutex);
  const auto node = find(impl_->root, key);
  if (!node) return fallback;
  if (!node->IsSequence()) throw ConfigError(origin(key), std::string(key), "expected a list of names, found a single value or map");
  std::vector<std::string> out;
  for (std::size_t i = 0; i < node->size(); ++i) {
    if (!(*node)[i].IsScalar())
      throw ConfigError(origin(key), std::string(key) + "[" + std::to_string(i) + "]", "expected a name, found a list or map");
    out.push_back((*node)[i].as<std::string>());
  }
  return out;
}

std::vector<std::string> Config::child_keys(std::string_view key) const {
  const Lock lock(impl_->mutex);
  std::vector<std::string> out;
  const auto node = key.empty() ? std::optional<YAML::Node>(impl_->root) : find(impl_->root, key);
  if (node && node->IsMap())
    for (const auto& kv : *node) out.push_back(kv.first.as<std::string>());
  return out;
}

// Reading no longer records anything, so there is nothing to check the keys against: the
// command's declared keys are (reject_unknown_keys(schema)). Kept only until config.hpp is next
// edited (every file includes it); nothing calls it.
void Config::reject_unknown_keys() const {
  throw std::logic_error("Config::reject_unknown_keys() needs the command's ConfigSchema: reject_unknown_keys(schema)");
}

void Config::reject_unknown_keys(const ConfigSchema& schema) const {
  for (const auto& leaf : leaf_keys())
    if (!schema.declares(leaf)) throw ConfigError(origin(leaf), leaf, "unknown key (misspelt, or not used by this command)");
}

std::vector<std::string> Config::leaf_keys() const {
  const Lock lock(impl_->mutex);
  std::vector<std::string> leaves;
  collect_leaves(impl_->root, "", leaves);
  return leaves;
}

std::string Config::dump(const ConfigSchema& schema) const {
  YAML::Node whole;
  {
    const Lock lock(impl_->mutex);
    whole = YAML::Clone(impl_->root);
  }
  for (const auto& key : schema.keys()) {
    if (key.is_map || key.no_default) continue;
    if (key.list) {
      YAML::Node list(YAML::NodeType::Sequence);
      for (const auto& item : key.defaults) list.push_back(item);
      insert_default(whole, key.name, list);
    } else {
      insert_default(whole, key.name, YAML::Node(key.defaults.front()));
    }
  }
  whole.SetStyle(YAML::EmitterStyle::Block);
  YAML::Emitter out;
  out << whole;
  return std::string(out.c_str()) + "\n";
}

std::string Config::dump() const {
  const Lock lock(impl_->mutex);
  YAML::Node whole = YAML::Clone(impl_->root);
  whole.SetStyle(YAML::EmitterStyle::Block);  // "{}" plus overrides would otherwise print as one line
  YAML::Emitter out;
  out << whole;
  return std::string(out.c_str()) + "\n";
}

}  // namespace navaid
