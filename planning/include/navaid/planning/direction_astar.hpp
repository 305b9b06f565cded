#pragma once
// Direction A* (eLabrador Alg. 1, eq. 11): a path toward a directional subgoal. Targets are n_s
// cells spread evenly along the boundary of the local window around the user; the chosen path
// minimises
//     cost = f_c(p_target) + alpha d(p_target) + beta (1 - cos theta)
// where f_c + alpha d is the grid objective of the path (map-cost integral + alpha x path length,
// as Alg. 1 line 7 adds alpha x path_length) and theta is the angle between the subgoal direction
// and the direction from the window centre (the user) to the target. Eq. (11) prints
// beta (cos theta + 1), which would favour targets *opposite* the subgoal; the text says the term
// penalises the angle to the subgoal, so we use 1 - cos theta (= cos(theta') + 1 with theta'
// measured from the reverse direction), 0 straight ahead and 2 behind.
//
// Alg. 1 runs one A* per target; here ONE search toward all targets at once (each target's
// terminal cost is its beta term, see best_first_search), which returns the same path as the
// best of the n_s separate searches. plan_separately() keeps Alg. 1's loop for tests and benches.
#include <vector>

#include "navaid/planning/grid_astar.hpp"

namespace navaid::planning {

struct DirectionAStarConfig {
  GridAStarConfig grid;        ///< alpha = grid.cost.length_weight
  int num_targets = 36;        ///< n_s (eLabrador does not give it: one per 10 degrees of a circle)
  double beta = 5.0;           ///< weight of the direction term [cost units]
  double window_m = 10.0;      ///< edge of the local window (eLabrador's 10 m x 10 m local map)
};

/// planning.direction_astar.num_targets in [1, 1000], .beta in [0, 1e4], .window_m in [1, 1000],
/// plus the grid and search keys.
DirectionAStarConfig read_direction_astar_config(const Config& config);

/// beta (1 - cos theta), theta = angle between `direction_rad` and (target - center).
double direction_term(double beta, double direction_rad, const Vec2& center, const Vec2& target);

/// The window of `window_m` around `center_W`, clipped to the grid.
CellWindow local_window(const mapping::GridGeometry& g, const Vec2& center_W, double window_m);

/// n cells evenly spaced along the boundary ring of `window` (walked counter-clockwise from its
/// lower-left corner), as linear grid indices; fewer when the ring has fewer cells.
std::vector<int> boundary_cells(const mapping::GridGeometry& g, const CellWindow& window, int n);

class DirectionAStarPlanner : public LocalPlanner {
 public:
  explicit DirectionAStarPlanner(const DirectionAStarConfig& config = {}) : config_(config) {}
  std::string_view name() const override { return "direction-astar"; }
  /// Needs problem.goal_direction_rad, or problem.goal_W (the direction toward it is used).
  Plan plan(const PlanningProblem& problem) const override;
  /// Alg. 1 as printed: one A* per target, then the minimum of eq. (11). Same answer as plan()
  /// (ties aside), n_s times the work; `expanded` sums every search.
  Plan plan_separately(const PlanningProblem& problem) const;

 private:
  DirectionAStarConfig config_;
};

}  // namespace navaid::planning
