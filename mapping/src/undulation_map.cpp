#include "navaid/mapping/undulation_map.hpp"

#include "navaid/mapping/config_schema.hpp"

#include <cmath>

namespace navaid::mapping {

namespace {
const ConfigKey<double> kStepThreshold{"mapping.undulation.step_threshold_m", UndulationConfig{}.step_threshold_m,
                                       {0.01, 2.0}, "a cell undulates when its Sobel edge degree exceeds this [m]"};
}  // namespace

ConfigSchema undulation_config_schema() { return ConfigSchema().add(kStepThreshold); }

UndulationConfig read_undulation_config(const Config& config) {
  UndulationConfig u;
  u.step_threshold_m = get(config, kStepThreshold);
  return u;
}

UndulationMap::UndulationMap(const GridGeometry& geometry) : GridLayer<std::uint8_t>(geometry, 0) {}

double sobel_edge_degree(const HeightMap& heights, const Cell2& c) {
  const GridGeometry& g = heights.geometry();
  const float center = heights.at(c);
  if (!HeightMap::is_known(center)) return 0.0;
  const auto h = [&](int dx, int dy) -> double {
    const Cell2 n(c.x() + dx, c.y() + dy);
    if (!g.contains(n)) return center;
    const float v = heights.at(n);
    return HeightMap::is_known(v) ? v : center;
  };
  const double gx = (h(1, -1) + 2.0 * h(1, 0) + h(1, 1)) - (h(-1, -1) + 2.0 * h(-1, 0) + h(-1, 1));
  const double gy = (h(-1, 1) + 2.0 * h(0, 1) + h(1, 1)) - (h(-1, -1) + 2.0 * h(0, -1) + h(1, -1));
  return 0.25 * std::sqrt(gx * gx + gy * gy);  // heights are small: no need for std::hypot's slow overflow care
}

UndulationMap build_undulation_map(const HeightMap& heights, const UndulationConfig& config) {
  UndulationMap map(heights.geometry());
  for (int y = 0; y < map.geometry().height(); ++y) {
    for (int x = 0; x < map.geometry().width(); ++x) {
      const Cell2 c(x, y);
      map.at(c) = sobel_edge_degree(heights, c) > config.step_threshold_m ? 1 : 0;
    }
  }
  return map;
}

}  // namespace navaid::mapping
