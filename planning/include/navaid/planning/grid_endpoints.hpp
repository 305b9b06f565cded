#pragma once
// Start and goal of a grid search as cells, with the reasons a search cannot begin: a point
// off the map, or inside an obstacle (or its clearance). Shared by A* and Direction A*.
#include <optional>
#include <string>

#include "navaid/planning/grid_search_space.hpp"
#include "navaid/planning/local_planner.hpp"

namespace navaid::planning {

/// The cell of p_W, or a Plan without a path explaining why it cannot be used (`what` names the
/// point, "start" or "goal", in the detail).
struct GridEndpoint {
  int index = -1;
  std::optional<Plan> failure;
};
GridEndpoint locate_endpoint(const mapping::CostMap& cost, const BlockedMask& blocked, const Vec2& p_W,
                             const char* what);

/// Cell centres of a search result, from the start cell to the end cell.
std::vector<Vec2> cell_path(const mapping::GridGeometry& g, const std::vector<int>& cells);

/// Fills a Plan from a search result (path, cost, counters, and the reason when not found).
template <class State>
Plan plan_from_search(const mapping::GridGeometry& g, const SearchResult<State>& r);

}  // namespace navaid::planning
