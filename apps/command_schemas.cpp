#include "command_schemas.hpp"

#include "navaid/estimation/config_schema.hpp"
#include "navaid/experiments/config_schema.hpp"
#include "navaid/interaction/config_schema.hpp"
#include "navaid/mapping/config_schema.hpp"
#include "navaid/planning/config_schema.hpp"
#include "navaid/simulation/config_schema.hpp"

namespace navaid::cli {

const ConfigKey<double>& octomap_camera_height_key() {
  static const ConfigKey<double> key{"planning.map.camera_z_m", 1.5, {-1000.0, 1000.0},
                                     "navaid plan on an OctoMap: the camera height its 2D layers are built for [m]"};
  return key;
}

ConfigKey<long long> flight_room_seed_key() {
  ConfigKey<long long> key = simulation::world_seed_key();
  key.fallback = 1;
  key.min = 1;
  key.max = 1LL << 62;
  return key;
}

ConfigSchema plan_map_schema() {
  return experiments::scenario_cost_map_schema()
      .add(planning::occupancy_cost_config_schema())
      .add(octomap_camera_height_key())
      .add(mapping::semantic_map_config_schema())
      .add(mapping::height_map_config_schema())
      .add(mapping::undulation_config_schema())
      .add(mapping::collision_config_schema())
      .add(mapping::cost_map_config_schema());
}

ConfigSchema apps_schema() { return ConfigSchema().add(octomap_camera_height_key()); }

ConfigSchema all_config_keys() {
  return ConfigSchema()
      .add(simulation::config_schema())
      .add(estimation::config_schema())
      .add(mapping::config_schema())
      .add(planning::config_schema())
      .add(interaction::config_schema())
      .add(experiments::config_schema())
      .add(apps_schema());
}

}  // namespace navaid::cli
