#pragma once
// A planning cost map from a 2D occupancy image (a real office map in map_server format, a
// scenario's ground-truth slice, an OctoMap slice): occupied cells cost 1, free cells 0 and
// unknown cells `unknown_cost`, on a GridGeometry whose origin is the image's lower-left corner
// snapped to whole cells. Planning takes the image, not io's file type: planning does not depend
// on io (DESIGN.md §2); the caller reads the file.
#include <cstdint>

#include "navaid/core/config.hpp"
#include "navaid/core/image.hpp"
#include "navaid/mapping/cost_map.hpp"

namespace navaid::planning {

using mapping::Vec2;

/// Per-pixel occupancy of an image whose row 0 is the top (largest y) of the map.
enum class OccupancyValue : std::uint8_t { kFree, kOccupied, kUnknown };

struct OccupancyCostConfig {
  double unknown_cost = 0.5;        ///< as mapping.cost.unknown_cost: passable, but not preferred
  double obstacle_threshold = 0.9;  ///< as mapping.cost.obstacle_threshold
  bool unknown_is_obstacle = false; ///< treat unseen space as blocked (conservative maps)
};

/// Keys planning.occupancy.unknown_cost in [0, 1], planning.occupancy.unknown_is_obstacle.
OccupancyCostConfig read_occupancy_cost_config(const Config& config);

/// `cells(x, y)` gives the occupancy of image pixel (x, y) (row 0 at the top); the map's
/// lower-left corner is origin_W. The grid's origin is origin_W snapped to the nearest whole
/// cell; `snap_offset_W` (if given) receives the shift (grid origin - origin_W), |shift| <= r/2.
template <class CellFn>
mapping::CostMap cost_map_from_occupancy(int width, int height, double resolution_m, const Vec2& origin_W,
                                         CellFn&& cells, const OccupancyCostConfig& config,
                                         Vec2* snap_offset_W = nullptr) {
  const mapping::Cell2 origin_cell((origin_W / resolution_m).array().round().cast<int>());
  mapping::CostMap cost(mapping::GridGeometry(origin_cell, width, height, resolution_m), config.obstacle_threshold,
                        0.0);
  if (snap_offset_W != nullptr) *snap_offset_W = origin_cell.cast<double>() * resolution_m - origin_W;
  const auto unknown = static_cast<float>(config.unknown_is_obstacle ? 1.0 : config.unknown_cost);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const OccupancyValue v = cells(x, height - 1 - y);
      cost.at(x, y) = v == OccupancyValue::kOccupied ? 1.0F : v == OccupancyValue::kFree ? 0.0F : unknown;
    }
  }
  return cost;
}

/// The same for an image in simulation's convention (0 occupied, 254 free, anything else unknown).
mapping::CostMap cost_map_from_occupancy_image(const ImageU8& image, double resolution_m, const Vec2& origin_W,
                                               const OccupancyCostConfig& config);

}  // namespace navaid::planning
