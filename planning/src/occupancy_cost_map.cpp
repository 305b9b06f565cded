#include "navaid/planning/occupancy_cost_map.hpp"

#include "navaid/planning/config_schema.hpp"

namespace navaid::planning {

namespace {
const ConfigKey<double> kUnknownCost{"planning.occupancy.unknown_cost", OccupancyCostConfig{}.unknown_cost, {0.0, 1.0},
                                     "cost of an unknown cell of an occupancy map (passable, not preferred)"};
// The same key as the mapping room's cost map (the schemas check that both agree).
const ConfigKey<double> kObstacleThreshold{"mapping.cost.obstacle_threshold", OccupancyCostConfig{}.obstacle_threshold,
                                           {0.0, 0.999}, "a cell is an obstacle at cost above this"};
const ConfigKey<bool> kUnknownIsObstacle{"planning.occupancy.unknown_is_obstacle",
                                         OccupancyCostConfig{}.unknown_is_obstacle,
                                         "treat unseen space of an occupancy map as blocked (conservative)"};
}  // namespace

ConfigSchema occupancy_cost_config_schema() {
  return ConfigSchema().add(kUnknownCost).add(kObstacleThreshold).add(kUnknownIsObstacle);
}

OccupancyCostConfig read_occupancy_cost_config(const Config& config) {
  OccupancyCostConfig c;
  c.unknown_cost = get(config, kUnknownCost);
  c.obstacle_threshold = get(config, kObstacleThreshold);
  c.unknown_is_obstacle = get(config, kUnknownIsObstacle);
  return c;
}

mapping::CostMap cost_map_from_occupancy_image(const ImageU8& image, double resolution_m, const Vec2& origin_W,
                                               const OccupancyCostConfig& config) {
  return cost_map_from_occupancy(
      image.width, image.height, resolution_m, origin_W,
      [&](int x, int y) {
        const std::uint8_t v = image.at(x, y);
        return v == 0 ? OccupancyValue::kOccupied : v >= 254 ? OccupancyValue::kFree : OccupancyValue::kUnknown;
      },
      config);
}

}  // namespace navaid::planning
