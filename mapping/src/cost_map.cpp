#include "navaid/mapping/cost_map.hpp"

#include <cassert>
#include <cmath>
#include <string>

#include "navaid/core/errors.hpp"
#include "navaid/mapping/config_schema.hpp"
#include "navaid/mapping/distance_transform.hpp"

namespace navaid::mapping {

namespace {
const CostMapConfig kCostMapDefaults;
const ConfigKey<double> kUnknownCost{"mapping.cost.unknown_cost", kCostMapDefaults.unknown_cost, {0.0, 1.0},
                                     "cost of a cell never seen occupied or free (not free, not an obstacle)"};
const ConfigKey<double> kObstacleThreshold{"mapping.cost.obstacle_threshold", kCostMapDefaults.obstacle_threshold, {0.0, 0.999},
                                           "a cell is an obstacle at cost above this (eLabrador Alg. 2: 0.9)"};
const ConfigKey<double> kInflationBase{"mapping.inflation.base_radius_m", kCostMapDefaults.inflation_base_radius_m, {0.0, 2.0},
                                       "inflation radius at zero position uncertainty [m]"};
const ConfigKey<double> kInflationKSigma{"mapping.inflation.k_sigma", kCostMapDefaults.inflation_k_sigma, {0.0, 10.0},
                                         "inflation grows by this times the horizontal position sigma"};
}  // namespace

ConfigSchema cost_map_config_schema() {
  return ConfigSchema().add(kUnknownCost).add(kObstacleThreshold).add(kInflationBase).add(kInflationKSigma);
}

CostMapConfig read_cost_map_config(const Config& config) {
  CostMapConfig c;
  c.unknown_cost = get(config, kUnknownCost);
  c.obstacle_threshold = get(config, kObstacleThreshold);
  c.inflation_base_radius_m = get(config, kInflationBase);
  c.inflation_k_sigma = get(config, kInflationKSigma);
  return c;
}

double inflation_radius_m(const CostMapConfig& config, double sigma_xy) {
  if (!std::isfinite(sigma_xy) || sigma_xy < 0.0) {
    throw Error("cost map: the horizontal position sigma_xy must be finite and >= 0, got " + std::to_string(sigma_xy));
  }
  return config.inflation_base_radius_m + config.inflation_k_sigma * sigma_xy;
}

CostMap::CostMap(const GridGeometry& geometry, double obstacle_threshold, double inflation_radius)
    : GridLayer<float>(geometry, 0.0F), obstacle_threshold_(obstacle_threshold), inflation_radius_m_(inflation_radius) {}

CostMap build_cost_map(const CollisionMap& collision, const UndulationMap& undulation, double sigma_xy,
                       const CostMapConfig& config) {
  assert(collision.geometry() == undulation.geometry());
  const double radius = inflation_radius_m(config, sigma_xy);
  const GridGeometry& g = collision.geometry();
  CostMap cost(g, config.obstacle_threshold, radius);
  ImageU8 obstacles(g.width(), g.height(), 1, 0);
  for (int y = 0; y < g.height(); ++y) {
    for (int x = 0; x < g.width(); ++x) {
      const float pt = collision.at(x, y);
      const double mt = CollisionMap::is_known(pt) ? pt : config.unknown_cost;
      cost.at(x, y) = static_cast<float>(fused_cost(mt, undulation.at(x, y)));
      obstacles.at(x, y) = cost.is_obstacle(x, y) ? 1 : 0;
    }
  }
  if (radius <= 0.0) return cost;
  // Blocked: centre within r of an obstacle cell's centre (exact distances, in cells).
  ImageF32 cells;
  distance_transform(obstacles, DistanceTransformBackend::kOpenCv, cells);
  const double radius_cells = radius / g.resolution();
  for (std::size_t i = 0; i < cells.pixels.size(); ++i) {
    if (cells.pixels[i] > 0.0F && cells.pixels[i] <= radius_cells) cost.cells().pixels[i] = 1.0F;
  }
  return cost;
}

}  // namespace navaid::mapping
