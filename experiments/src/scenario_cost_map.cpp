#include "navaid/experiments/scenario_cost_map.hpp"

#include <fmt/format.h>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/config_schema.hpp"
#include "navaid/planning/config_schema.hpp"
#include "navaid/planning/occupancy_cost_map.hpp"
#include "navaid/simulation/occupancy_export.hpp"
#include "navaid/simulation/scenario.hpp"

namespace navaid::experiments {

namespace {
const ConfigKey<double> kResolution{"planning.map.resolution_m", 0.1, {0.01, 2.0},
                                    "cell size of a scenario's planner map [m]"};
const ConfigKey<std::vector<double>> kBand{"planning.map.band_m", std::vector<double>{0.2, 2.0}, 2, {-10.0, 10.0},
                                           "[low, high] height band above the ground sliced into a scenario's "
                                           "planner map [m]"};
}  // namespace

ConfigSchema scenario_cost_map_schema() {
  return ConfigSchema().add(kResolution).add(kBand).add(planning::occupancy_cost_config_schema());
}

ScenarioCostMap scenario_cost_map(const std::string& scenario, const Config& config) {
  const double resolution = get(config, kResolution);
  const std::vector<double> band = get(config, kBand);
  if (!(band[1] > band[0])) throw ConfigError("", "planning.map.band_m", "needs low < high");
  simulation::ScenarioOptions options;
  options.people = options.vehicles = false;
  const simulation::Scenario s = simulation::make_scenario(scenario, options);
  const simulation::OccupancyGrid3D grid = simulation::voxelize(s.world, resolution, s.world.bounds());
  const ImageU8 slice = simulation::occupancy_slice(grid, s.ground_z_m + band[0], s.ground_z_m + band[1]);
  return ScenarioCostMap{planning::cost_map_from_occupancy_image(slice, resolution, grid.origin.head<2>(),
                                                                 planning::read_occupancy_cost_config(config)),
                         fmt::format("scenario {} (band {:.2f}..{:.2f} m above the ground, {} m cells)", scenario,
                                     band[0], band[1], resolution)};
}

}  // namespace navaid::experiments
