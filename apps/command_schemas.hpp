#pragma once
// The configuration keys of the navaid program: the apps' own keys, the schema each command reads
// (the union of the rooms' schemas it uses) and every key at once (navaid config --list).
#include "navaid/core/config_schema.hpp"

namespace navaid::cli {

/// planning.map.camera_z_m: the camera height an OctoMap's 2D layers are built for (navaid plan).
const ConfigKey<double>& octomap_camera_height_key();
/// simulation.world_seed as --from-recording's flight room reads it (default 1, at least 1).
ConfigKey<long long> flight_room_seed_key();

/// The keys load_plan_map reads, whatever the map (scenario, map_server, OctoMap or semantic map).
ConfigSchema plan_map_schema();

/// The keys the apps read themselves.
ConfigSchema apps_schema();

/// Every configuration key navaid declares.
ConfigSchema all_config_keys();

}  // namespace navaid::cli
