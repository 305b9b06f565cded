#pragma once
// A device preset: one YAML file under runtime/devices/ that says which layers a full-device
// run joins and how (docs/full-device-runs.md): the guidance chain, the actuator, speech, what the
// recording must carry, and the estimator / mapping / planning / interaction keys of that device.
// Any key can be changed with --set like every other configuration.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/interaction/actuator_pattern.hpp"

namespace navaid::runtime {

/// The planning chain that turns estimates and maps into GuidanceCommands.
enum class GuidanceKind {
  kRoute,           ///< eLabrador: walking route -> directional subgoal -> Direction A* -> path following
  kWalkingPath,     ///< Smart Cane: ESDF + walking-path generator re-planning at 10 Hz + PI steering
  kObstacleRumble,  ///< BYU augmented cane: PCL obstacle scan -> FICF / CACF -> rumble table
  kHandTarget,      ///< W-ROMA: AprilTag-marked target -> hand guidance cases I / II / III
};
std::string_view to_string(GuidanceKind kind);

struct DeviceSpec {
  std::string name;
  GuidanceKind guidance = GuidanceKind::kRoute;
  interaction::DeviceKind actuator = interaction::DeviceKind::kBelt;
  std::string speech = "on";  ///< on (espeak-ng, speech.wav) | text | off
  bool needs_depth = true;    ///< device.needs: depth
  bool needs_gps = false;     ///< device.needs: gps
  /// Map every n-th estimate (the planners read the newest map; mapping is the costly stage); 0:
  /// never (a device whose guidance needs no map).
  std::size_t map_every = 1;
  /// kRoute: the OSM file of the streets (empty: the simulated scenario's own streets) and the
  /// destination (lat, lon; empty: the end of the scenario's path).
  std::filesystem::path route_osm;
  std::optional<std::pair<double, double>> route_to;
  /// kRoute: the landmark the user should face on arrival (lat, lon; empty: the simulated
  /// scenario's goal landmark, none on a real map).
  std::optional<std::pair<double, double>> route_face;
  /// kWalkingPath: the goal in the start pose's frame (forward, left) [m]; empty: the end of the
  /// simulated scenario's path.
  std::optional<std::pair<double, double>> goal_start_frame_m;
};

/// Reads device.* (ConfigError naming the key on a bad value).
DeviceSpec read_device_spec(const Config& config);

/// The folder of the presets: $NAVAID_DEVICES_DIR, else the source tree's runtime/devices,
/// else the installed share/navaid/devices.
std::filesystem::path devices_dir();
/// The presets' names (the YAML files in devices_dir()), sorted.
std::vector<std::string> device_preset_names();
/// The preset's file; UsageError listing the presets when there is none of that name.
std::filesystem::path device_preset_file(const std::string& name);

}  // namespace navaid::runtime
