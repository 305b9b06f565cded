#include "navaid/mapping/grid_geometry.hpp"

#include <cassert>
#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/mapping/config_schema.hpp"

namespace navaid::mapping {

namespace {
const ConfigKey<double> kGridGeometryResolution{"mapping.grid.resolution_m", GridConfig{}.resolution_m, {0.01, 1.0},
                                    "cell edge of the 2D layers [m]"};
const ConfigKey<double> kSize{"mapping.grid.size_m", GridConfig{}.size_m, {1.0, 100.0},
                              "edge of the 2D window around the user [m] (at least 3 cells)"};
}  // namespace

ConfigSchema grid_config_schema() { return ConfigSchema().add(kGridGeometryResolution).add(kSize); }

GridConfig read_grid_config(const Config& config) {
  GridConfig g;
  g.resolution_m = get(config, kGridGeometryResolution);
  g.size_m = get(config, kSize);
  if (std::lround(g.size_m / g.resolution_m) < 3) {
    const std::string key = config.has("mapping.grid.size_m") ? "mapping.grid.size_m" : "mapping.grid.resolution_m";
    throw ConfigError(config.origin(key), key,
                      "the window must hold at least 3 x 3 cells (size_m / resolution_m >= 3)");
  }
  return g;
}

GridGeometry::GridGeometry(const Cell2& origin_cell, int width, int height, double resolution_m)
    : origin_(origin_cell), width_(width), height_(height), resolution_(resolution_m) {
  assert(resolution_m > 0.0 && width > 0 && height > 0);
}

GridGeometry GridGeometry::around(const Vec2& center_W, const GridConfig& config) {
  const int n = static_cast<int>(std::lround(config.size_m / config.resolution_m));
  const Cell2 center(static_cast<int>(std::floor(center_W.x() / config.resolution_m)),
                     static_cast<int>(std::floor(center_W.y() / config.resolution_m)));
  return GridGeometry(center - Cell2(n / 2, n / 2), n, n, config.resolution_m);
}

Cell2 GridGeometry::world_cell(const Vec2& p_W) const {
  return Cell2(static_cast<int>(std::floor(p_W.x() / resolution_)), static_cast<int>(std::floor(p_W.y() / resolution_)));
}

}  // namespace navaid::mapping
