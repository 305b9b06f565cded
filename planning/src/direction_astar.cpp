#include "navaid/planning/direction_astar.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "navaid/core/errors.hpp"
#include "navaid/planning/config_schema.hpp"
#include "navaid/planning/grid_endpoints.hpp"

namespace navaid::planning {

namespace {
const DirectionAStarConfig kDirectionAstarDefaults;
const ConfigKey<int> kNumTargets{"planning.direction_astar.num_targets", kDirectionAstarDefaults.num_targets, 1, 1000,
                                 "n_s: boundary targets of Direction A* (one per 10 deg by default)"};
const ConfigKey<double> kBeta{"planning.direction_astar.beta", kDirectionAstarDefaults.beta, {0.0, 1e4},
                              "weight of Direction A*'s direction term [cost units]"};
const ConfigKey<double> kDirectionAstarWindow{"planning.direction_astar.window_m", kDirectionAstarDefaults.window_m, {1.0, 1000.0},
                                "edge of Direction A*'s local window [m]"};
}  // namespace

ConfigSchema direction_astar_config_schema() {
  return grid_astar_config_schema().add(kNumTargets).add(kBeta).add(kDirectionAstarWindow);
}

DirectionAStarConfig read_direction_astar_config(const Config& config) {
  DirectionAStarConfig c;
  c.grid = read_grid_astar_config(config);
  c.num_targets = get(config, kNumTargets);
  c.beta = get(config, kBeta);
  c.window_m = get(config, kDirectionAstarWindow);
  return c;
}

double direction_term(double beta, double direction_rad, const Vec2& center, const Vec2& target) {
  const Vec2 d = target - center;
  const double n = d.norm();
  if (n == 0.0) return beta;  // no direction: treat as perpendicular
  const double cos_theta = (d.x() * std::cos(direction_rad) + d.y() * std::sin(direction_rad)) / n;
  return beta * (1.0 - cos_theta);
}

CellWindow local_window(const mapping::GridGeometry& g, const Vec2& center_W, double window_m) {
  const mapping::Cell2 c = g.cell_of(center_W);
  const int half = std::max(1, static_cast<int>(std::lround(0.5 * window_m / g.resolution())));
  CellWindow w;
  w.x0 = std::clamp(c.x() - half, 0, g.width());
  w.y0 = std::clamp(c.y() - half, 0, g.height());
  w.x1 = std::clamp(c.x() + half + 1, 0, g.width());
  w.y1 = std::clamp(c.y() + half + 1, 0, g.height());
  return w;
}

std::vector<int> boundary_cells(const mapping::GridGeometry& g, const CellWindow& w, int n) {
  std::vector<int> ring;
  if (w.x1 <= w.x0 || w.y1 <= w.y0) return ring;
  const auto add = [&](int x, int y) { ring.push_back(y * g.width() + x); };
  if (w.x1 - w.x0 == 1 || w.y1 - w.y0 == 1) {
    for (int y = w.y0; y < w.y1; ++y)
      for (int x = w.x0; x < w.x1; ++x) add(x, y);
  } else {
    for (int x = w.x0; x < w.x1 - 1; ++x) add(x, w.y0);       // bottom, left to right
    for (int y = w.y0; y < w.y1 - 1; ++y) add(w.x1 - 1, y);   // right, upwards
    for (int x = w.x1 - 1; x > w.x0; --x) add(x, w.y1 - 1);   // top, right to left
    for (int y = w.y1 - 1; y > w.y0; --y) add(w.x0, y);       // left, downwards
  }
  if (static_cast<int>(ring.size()) <= n) return ring;
  std::vector<int> picked;
  picked.reserve(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    picked.push_back(ring[static_cast<std::size_t>(k) * ring.size() / static_cast<std::size_t>(n)]);
  }
  return picked;
}

namespace {

struct DirectionSetup {
  std::optional<Plan> failure;
  int start = -1;
  CellWindow window;
  std::vector<GridTarget> targets;
};

DirectionSetup set_up(const DirectionAStarConfig& config, const PlanningProblem& problem, const BlockedMask& blocked) {
  if (problem.cost == nullptr) throw Error("direction-astar: the planning problem has no cost map");
  if (!problem.goal_direction_rad && !problem.goal_W) {
    throw Error("direction-astar: needs a directional subgoal or a point goal to take the direction from");
  }
  const mapping::CostMap& cost = *problem.cost;
  const mapping::GridGeometry& g = cost.geometry();
  DirectionSetup s;
  const GridEndpoint start = locate_endpoint(cost, blocked, problem.start.position, "start");
  if (start.failure) {
    s.failure = start.failure;
    return s;
  }
  s.start = start.index;
  const Vec2 center = problem.start.position;
  const double direction = problem.goal_direction_rad
                               ? *problem.goal_direction_rad
                               : std::atan2(problem.goal_W->y() - center.y(), problem.goal_W->x() - center.x());
  s.window = local_window(g, center, config.window_m);
  for (const int cell : boundary_cells(g, s.window, config.num_targets)) {
    if (blocked.blocked(cell)) continue;
    const Vec2 p = g.cell_center(mapping::Cell2(cell % g.width(), cell / g.width()));
    s.targets.push_back(GridTarget{cell, direction_term(config.beta, direction, center, p)});
  }
  if (s.targets.empty()) {
    Plan p;
    p.reason = GuidanceReason::kNoPath;
    p.detail = fmt::format("every one of the {} boundary targets of the {:.1f} m window is blocked",
                           config.num_targets, config.window_m);
    s.failure = p;
  }
  return s;
}

double clearance(const DirectionAStarConfig& config, const PlanningProblem& problem) {
  return config.grid.cost.base_clearance_m + config.grid.cost.clearance_k_sigma * problem.sigma_xy_m;
}

}  // namespace

Plan DirectionAStarPlanner::plan(const PlanningProblem& problem) const {
  if (problem.cost == nullptr) throw Error("direction-astar: the planning problem has no cost map");
  const BlockedMask blocked(*problem.cost, problem.esdf, clearance(config_, problem));
  DirectionSetup s = set_up(config_, problem, blocked);
  if (s.failure) return *s.failure;
  const GridSearchSpace<TargetSet> space(*problem.cost, blocked, config_.grid.cost, s.window,
                                         TargetSet{std::move(s.targets)});
  return plan_from_search(problem.cost->geometry(), best_first_search(space, s.start, config_.grid.limits));
}

Plan DirectionAStarPlanner::plan_separately(const PlanningProblem& problem) const {
  if (problem.cost == nullptr) throw Error("direction-astar: the planning problem has no cost map");
  const BlockedMask blocked(*problem.cost, problem.esdf, clearance(config_, problem));
  const DirectionSetup s = set_up(config_, problem, blocked);
  if (s.failure) return *s.failure;
  const mapping::GridGeometry& g = problem.cost->geometry();
  Plan best;
  best.cost = std::numeric_limits<double>::infinity();
  std::size_t expanded = 0;
  double time_s = 0.0;
  for (const GridTarget& t : s.targets) {
    const GridSearchSpace<PointGoal> space(*problem.cost, blocked, config_.grid.cost, s.window, PointGoal{t.index});
    Plan p = plan_from_search(g, best_first_search(space, s.start, config_.grid.limits));
    expanded += p.expanded;
    time_s += p.time_s;
    if (p.found()) p.cost += t.terminal_cost;
    if (p.found() && (!best.found() || p.cost < best.cost)) best = std::move(p);
    else if (!best.found() && !p.found()) best = std::move(p);
  }
  best.expanded = expanded;
  best.time_s = time_s;
  return best;
}

}  // namespace navaid::planning
