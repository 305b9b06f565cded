#pragma once
// Plain A* on the cost map toward one point goal: the eLabrador path search's inner search and
// the Smart Cane's A* baseline. Objective: alpha x length + w_c x integral of the map cost.
#include "navaid/planning/grid_search_space.hpp"
#include "navaid/planning/local_planner.hpp"

namespace navaid::planning {

struct GridAStarConfig {
  GridCostConfig cost;
  SearchLimits limits;
};

/// planning.grid.* and planning.search.* keys.
GridAStarConfig read_grid_astar_config(const Config& config);

class GridAStarPlanner : public LocalPlanner {
 public:
  explicit GridAStarPlanner(const GridAStarConfig& config = {}) : config_(config) {}
  std::string_view name() const override { return "astar"; }
  /// Needs problem.goal_W; throws navaid::Error without a cost map or a point goal.
  Plan plan(const PlanningProblem& problem) const override;

 private:
  GridAStarConfig config_;
};

}  // namespace navaid::planning
