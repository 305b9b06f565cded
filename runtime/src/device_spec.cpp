#include "navaid/runtime/device_spec.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>

#include "navaid/core/enum_names.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/runtime/config_schema.hpp"

namespace navaid::runtime {

namespace {

constexpr NameTable<GuidanceKind, 4> kGuidanceNames{{
    {GuidanceKind::kRoute, "route"},
    {GuidanceKind::kWalkingPath, "walking-path"},
    {GuidanceKind::kObstacleRumble, "obstacle-rumble"},
    {GuidanceKind::kHandTarget, "hand-target"},
}};

std::optional<std::pair<double, double>> optional_pair(const Config& config,
                                                       const ConfigKey<std::vector<double>>& key) {
  if (!config.has(key.name)) return std::nullopt;
  const std::vector<double> v = get(config, key);
  return std::make_pair(v[0], v[1]);
}

const ConfigKey<std::string> kName{"device.name", std::nullopt, {}, "the device preset's name (--device NAME)"};
const ConfigKey<std::string> kGuidance{"device.guidance", std::nullopt, enum_names(kGuidanceNames),
                                       "the device's guidance chain"};
const ConfigKey<std::string> kActuator{"device.actuator", std::nullopt, {"belt", "hand", "rumble", "wheel"},
                                       "the device's actuator"};
const ConfigKey<std::string> kSpeech{"device.speech", std::nullopt, {"on", "text", "off"},
                                     "speech: espeak-ng (on), text only, or none; absent: on"};
const ConfigKey<std::vector<std::string>> kNeeds{"device.needs", {"depth"}, "the sensors the device needs: depth, gps"};
const ConfigKey<int> kMapEvery{"device.map_every", 1, 0, 100, "map every n-th estimate; 0: never"};
const ConfigKey<std::string> kRouteOsm{"device.route.osm", std::nullopt, {},
                                       "route guidance: the OpenStreetMap extract; absent: the scenario's streets"};
const ConfigKey<std::vector<double>> kRouteTo{"device.route.to", std::nullopt, 2, {-180.0, 180.0},
                                              "route guidance: the destination [lat, lon]; absent: the path's end"};
const ConfigKey<std::vector<double>> kRouteFace{"device.route.face", std::nullopt, 2, {-180.0, 180.0},
                                                "route guidance: the landmark to face on arrival [lat, lon]"};
const ConfigKey<std::vector<double>> kGoalStartFrame{"device.goal_start_frame_m", std::nullopt, 2, {-1000.0, 1000.0},
                                                     "walking-path guidance: the goal in the start pose's frame "
                                                     "[forward, left] [m]; absent: the path's end"};

}  // namespace

const ConfigKey<std::string>& device_guidance_key() { return kGuidance; }
const ConfigKey<std::string>& device_actuator_key() { return kActuator; }

ConfigSchema device_spec_schema() {
  return ConfigSchema()
      .add(kName)
      .add(kGuidance)
      .add(kActuator)
      .add(kSpeech)
      .add(kNeeds)
      .add(kMapEvery)
      .add(kRouteOsm)
      .add(kRouteTo)
      .add(kRouteFace)
      .add(kGoalStartFrame);
}

std::string_view to_string(GuidanceKind kind) { return enum_name(kGuidanceNames, kind, "?"); }

DeviceSpec read_device_spec(const Config& config) {
  DeviceSpec s;
  s.name = get(config, kName);
  // get allows the table's names only, so enum_value finds every name it returns.
  s.guidance = *enum_value(kGuidanceNames, get(config, kGuidance));
  s.actuator = *interaction::device_kind_from_string(get(config, kActuator));
  if (config.has(kSpeech.name)) s.speech = get(config, kSpeech);
  s.needs_depth = false;
  for (const std::string& need : get(config, kNeeds)) {
    if (need == "depth") {
      s.needs_depth = true;
    } else if (need == "gps") {
      s.needs_gps = true;
    } else {
      throw ConfigError(config.origin("device.needs"), "device.needs", "'" + need + "' is not depth or gps");
    }
  }
  s.map_every = static_cast<std::size_t>(get(config, kMapEvery));
  if (config.has(kRouteOsm.name)) s.route_osm = get(config, kRouteOsm);
  s.route_to = optional_pair(config, kRouteTo);
  s.route_face = optional_pair(config, kRouteFace);
  s.goal_start_frame_m = optional_pair(config, kGoalStartFrame);
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
