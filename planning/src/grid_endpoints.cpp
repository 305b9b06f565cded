#include "navaid/planning/grid_endpoints.hpp"

#include <fmt/format.h>

namespace navaid::planning {

GridEndpoint locate_endpoint(const mapping::CostMap& cost, const BlockedMask& blocked, const Vec2& p_W,
                             const char* what) {
  GridEndpoint e;
  const mapping::GridGeometry& g = cost.geometry();
  const mapping::Cell2 c = g.cell_of(p_W);
  const bool start = std::string(what) == "start";
  if (!p_W.allFinite() || !g.contains(c)) {
    Plan p;
    p.reason = GuidanceReason::kOffMap;
    const mapping::Vec2 lo = g.origin_W();
    const mapping::Vec2 hi = lo + mapping::Vec2(g.width(), g.height()) * g.resolution();
    p.detail = fmt::format("{} ({:.2f}, {:.2f}) is off the map [{:.2f}, {:.2f}] x [{:.2f}, {:.2f}]", what, p_W.x(),
                           p_W.y(), lo.x(), hi.x(), lo.y(), hi.y());
    e.failure = p;
    return e;
  }
  e.index = static_cast<int>(g.index(c));
  if (blocked.blocked(e.index)) {
    Plan p;
    p.reason = start ? GuidanceReason::kStartBlocked : GuidanceReason::kGoalBlocked;
    p.detail = cost.is_obstacle(c)
                   ? fmt::format("{} ({:.2f}, {:.2f}) lies in an obstacle (cost {:.2f} > {:.2f})", what, p_W.x(),
                                 p_W.y(), cost.at(c), cost.obstacle_threshold())
                   : fmt::format("{} ({:.2f}, {:.2f}) lies within the clearance {:.2f} m of an obstacle", what,
                                 p_W.x(), p_W.y(), blocked.clearance_m());
    e.failure = p;
    e.index = -1;
  }
  return e;
}

std::vector<Vec2> cell_path(const mapping::GridGeometry& g, const std::vector<int>& cells) {
  std::vector<Vec2> path;
  path.reserve(cells.size());
  for (const int i : cells) path.push_back(g.cell_center(mapping::Cell2(i % g.width(), i / g.width())));
  return path;
}

template <class State>
Plan plan_from_search(const mapping::GridGeometry& g, const SearchResult<State>& r) {
  Plan p = plan_outcome(r.status, r.expanded, r.time_s);
  if (r.found()) {
    p.path_W = cell_path(g, r.path);
    p.length_m = polyline_length(p.path_W);
    p.cost = r.cost;
  }
  return p;
}

template Plan plan_from_search<int>(const mapping::GridGeometry& g, const SearchResult<int>& r);

}  // namespace navaid::planning
