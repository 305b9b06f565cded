#include "navaid/planning/grid_astar.hpp"

#include "navaid/core/errors.hpp"
#include "navaid/planning/config_schema.hpp"
#include "navaid/planning/grid_endpoints.hpp"

namespace navaid::planning {

ConfigSchema grid_astar_config_schema() { return grid_cost_config_schema().add(search_limits_schema()); }

GridAStarConfig read_grid_astar_config(const Config& config) {
  return GridAStarConfig{read_grid_cost_config(config), read_search_limits(config)};
}

Plan GridAStarPlanner::plan(const PlanningProblem& problem) const {
  if (problem.cost == nullptr) throw Error("astar: the planning problem has no cost map");
  if (!problem.goal_W) throw Error("astar: needs a point goal (a directional subgoal needs direction-astar)");
  const mapping::CostMap& cost = *problem.cost;
  const mapping::GridGeometry& g = cost.geometry();
  const BlockedMask blocked(cost, problem.esdf,
                            config_.cost.base_clearance_m + config_.cost.clearance_k_sigma * problem.sigma_xy_m);
  const GridEndpoint start = locate_endpoint(cost, blocked, problem.start.position, "start");
  if (start.failure) return *start.failure;
  const GridEndpoint goal = locate_endpoint(cost, blocked, *problem.goal_W, "goal");
  if (goal.failure) return *goal.failure;
  const GridSearchSpace<PointGoal> space(cost, blocked, config_.cost, CellWindow{0, 0, g.width(), g.height()},
                                         PointGoal{goal.index});
  return plan_from_search(g, best_first_search(space, start.index, config_.limits));
}

}  // namespace navaid::planning
