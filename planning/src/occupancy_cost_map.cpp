#include "navaid/planning/occupancy_cost_map.hpp"

namespace navaid::planning {

OccupancyCostConfig read_occupancy_cost_config(const Config& config) {
  OccupancyCostConfig c;
  c.unknown_cost = config.get_double("planning.occupancy.unknown_cost", c.unknown_cost, {0.0, 1.0});
  c.obstacle_threshold = config.get_double("mapping.cost.obstacle_threshold", c.obstacle_threshold, {0.0, 0.999});
  c.unknown_is_obstacle = config.get_bool("planning.occupancy.unknown_is_obstacle", c.unknown_is_obstacle);
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
