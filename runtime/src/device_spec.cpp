#include "navaid/runtime/device_spec.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>

#include "navaid/core/enum_names.hpp"
#include "navaid/core/errors.hpp"

namespace navaid::runtime {

namespace {

constexpr NameTable<GuidanceKind, 4> kGuidanceNames{{
    {GuidanceKind::kRoute, "route"},
    {GuidanceKind::kWalkingPath, "walking-path"},
    {GuidanceKind::kObstacleRumble, "obstacle-rumble"},
    {GuidanceKind::kHandTarget, "hand-target"},
}};

std::optional<std::pair<double, double>> optional_pair(const Config& config, const std::string& key,
                                                       Range allowed) {
  if (!config.has(key)) return std::nullopt;
  const std::vector<double> v = config.get_doubles(key, 2, allowed);
  return std::make_pair(v[0], v[1]);
}

}  // namespace

std::string_view to_string(GuidanceKind kind) { return enum_name(kGuidanceNames, kind, "?"); }

DeviceSpec read_device_spec(const Config& config) {
  DeviceSpec s;
  s.name = config.get_string("device.name");
  // get_string allows the table's names only, so enum_value finds every name it returns.
  s.guidance = *enum_value(kGuidanceNames, config.get_string("device.guidance", enum_names(kGuidanceNames)));
  s.actuator = *interaction::device_kind_from_string(config.get_string("device.actuator", {"belt", "hand", "rumble", "wheel"}));
  if (config.has("device.speech")) s.speech = config.get_string("device.speech", std::string("on"), {"on", "text", "off"});
  s.needs_depth = false;
  for (const std::string& need : config.get_strings("device.needs", {"depth"})) {
    if (need == "depth") {
      s.needs_depth = true;
    } else if (need == "gps") {
      s.needs_gps = true;
    } else {
      throw ConfigError(config.origin("device.needs"), "device.needs", "'" + need + "' is not depth or gps");
    }
  }
  s.map_every = static_cast<std::size_t>(config.get_int("device.map_every", 1, 0, 100));
  if (config.has("device.route.osm")) s.route_osm = config.get_string("device.route.osm");
  s.route_to = optional_pair(config, "device.route.to", {-180.0, 180.0});
  s.route_face = optional_pair(config, "device.route.face", {-180.0, 180.0});
  s.goal_start_frame_m = optional_pair(config, "device.goal_start_frame_m", {-1000.0, 1000.0});
  return s;
}

std::filesystem::path devices_dir() {
  if (const char* env = std::getenv("NAVAID_DEVICES_DIR")) return env;
  if (std::filesystem::is_directory(NAVAID_SOURCE_DEVICES_DIR)) return NAVAID_SOURCE_DEVICES_DIR;
  return NAVAID_INSTALLED_DEVICES_DIR;
}

std::vector<std::string> device_preset_names() {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(devices_dir(), ec))
    if (entry.path().extension() == ".yaml") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::filesystem::path device_preset_file(const std::string& name) {
  const std::filesystem::path file = devices_dir() / (name + ".yaml");
  if (std::filesystem::is_regular_file(file)) return file;
  throw UsageError(fmt::format("no device preset '{}' in {} (presets: {})", name, devices_dir().string(),
                               fmt::join(device_preset_names(), ", ")));
}

}  // namespace navaid::runtime
