#pragma once
// Cost map M_c, eLabrador eq. (8): M_c = M_t (1 - M_h) + M_h, the collision map where the ground is
// flat and 1 where it undulates; then obstacles (cost > obstacle_threshold) are inflated by the
// uncertainty of the user's horizontal position, r = base_radius_m + k_sigma * sigma_xy: a cell
// within r of an obstacle may be the obstacle's true place, so it is blocked (cost 1) too.
#include "navaid/core/config.hpp"
#include "navaid/mapping/collision_map.hpp"
#include "navaid/mapping/undulation_map.hpp"

namespace navaid::mapping {

struct CostMapConfig {
  /// Cost of a cell whose collision probability is unknown (no occupied voxel seen): not free, so
  /// planners prefer seen ground, and not an obstacle, so they may plan into the unseen.
  double unknown_cost = 0.5;
  /// A cell is an obstacle at cost > this (eLabrador Alg. 2 checks collisions at cost > 0.9).
  double obstacle_threshold = 0.9;
  /// Inflation radius r = base_radius_m + k_sigma * sigma_xy [m]. The base is 0: the user's body
  /// belongs to the planner's footprint (WPG's spheres), not to the map.
  double inflation_base_radius_m = 0.0;
  double inflation_k_sigma = 2.0;
};

/// Keys mapping.cost.unknown_cost in [0, 1], mapping.cost.obstacle_threshold in [0, 1),
/// mapping.inflation.base_radius_m in [0, 2], mapping.inflation.k_sigma in [0, 10].
CostMapConfig read_cost_map_config(const Config& config);

/// Eq. (8) for one cell: collision p(g) in [0, 1], undulation 0 or 1.
inline double fused_cost(double collision, double undulation) { return collision * (1.0 - undulation) + undulation; }

/// r = base + k sigma_xy [m]; throws navaid::Error when sigma_xy is not finite or negative.
double inflation_radius_m(const CostMapConfig& config, double sigma_xy);

/// Cell value: cost in [0, 1] after inflation.
class CostMap : public GridLayer<float> {
 public:
  CostMap(const GridGeometry& geometry, double obstacle_threshold, double inflation_radius_m);
  double obstacle_threshold() const { return obstacle_threshold_; }
  double inflation_radius_m() const { return inflation_radius_m_; }
  bool is_obstacle(const Cell2& c) const { return at(c) > obstacle_threshold_; }
  bool is_obstacle(int x, int y) const { return at(x, y) > obstacle_threshold_; }

 private:
  double obstacle_threshold_;
  double inflation_radius_m_;
};

/// Fuses the layers (same geometry, asserted) with eq. (8) and inflates obstacles by
/// inflation_radius_m(config, sigma_xy): every cell whose centre lies within r of an obstacle
/// cell's centre gets cost 1. sigma_xy is the horizontal position standard deviation of the
/// estimate [m] (mapping::pose_uncertainty); a non-finite or negative value throws navaid::Error.
CostMap build_cost_map(const CollisionMap& collision, const UndulationMap& undulation, double sigma_xy,
                       const CostMapConfig& config);

}  // namespace navaid::mapping
