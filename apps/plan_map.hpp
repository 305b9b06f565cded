#pragma once
// The maps `navaid plan` (and the planning reproductions' users) plan on, from what a user has:
//   scenario:NAME         a simulator scenario's ground truth: the occupancy of the body's height band
//   FILE.yaml             a ROS map_server map (a real office map, `navaid scenario-map` output)
//   FILE.bt / FILE.ot     an OctoMap (a real 3D map, `navaid map`'s map.ot) through the mapping layers
//                         (height, undulation, collision eq. 9, cost eq. 8)
//   DIR                   a `navaid map` output (map.ot) or a folder holding one map_server YAML
#include <filesystem>
#include <string>

#include "navaid/core/config.hpp"
#include "navaid/mapping/cost_map.hpp"

namespace navaid::cli {

struct PlanMap {
  mapping::CostMap cost;
  std::string description;  ///< what was read, in words (for the JSON and the console)
};

/// Keys: planning.map.resolution_m (scenario maps, default 0.1), planning.map.band_m ([low, high]
/// above the scenario's ground, default [0.2, 2.0]), planning.map.camera_z_m (OctoMaps: the
/// camera's height in the map frame for eq. 9, default 1.5), planning.occupancy.*, and the
/// mapping.* keys of the 2D layers. Throws IoError / ConfigError / UsageError naming the input.
PlanMap load_plan_map(const std::string& spec, const Config& config);

}  // namespace navaid::cli
