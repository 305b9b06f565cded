#include "navaid/planning/local_planner.hpp"

#include <fmt/format.h>

#include "navaid/core/errors.hpp"
#include "navaid/planning/config_schema.hpp"
#include "navaid/planning/direction_astar.hpp"
#include "navaid/planning/grid_astar.hpp"
#include "navaid/planning/wpg_planner.hpp"

namespace navaid::planning {

namespace {
const ConfigKey<long long> kLocalPlannerMaxExpansions{"planning.search.max_expansions",
                                          static_cast<long long>(SearchLimits{}.max_expansions), 1, 1'000'000'000,
                                          "a search stops after taking this many nodes off its open list"};
const ConfigKey<double> kMaxTime{"planning.search.max_time_s", SearchLimits{}.max_time_s, {0.0, 3600.0},
                                 "wall-clock limit of a search [s]; 0 = none (replay stays deterministic)"};
}  // namespace

ConfigSchema search_limits_schema() { return ConfigSchema().add(kLocalPlannerMaxExpansions).add(kMaxTime); }

SearchLimits read_search_limits(const Config& config) {
  SearchLimits l;
  l.max_expansions = static_cast<std::size_t>(get(config, kLocalPlannerMaxExpansions));
  l.max_time_s = get(config, kMaxTime);
  return l;
}

ConfigSchema config_schema() {
  return ConfigSchema()
      .add(search_limits_schema())
      .add(grid_astar_config_schema())
      .add(direction_astar_config_schema())
      .add(wpg_config_schema())
      .add(occupancy_cost_config_schema())
      .add(path_guidance_config_schema())
      .add(pi_heading_config_schema())
      .add(smart_cane_guidance_config_schema())
      .add(byu_cost_config_schema())
      .add(hand_guidance_config_schema())
      .add(apriltag_detector_config_schema())
      .add(foot_route_config_schema())
      .add(narration_config_schema())
      .add(sub_route_config_schema());
}

ConfigSchema local_planner_schema(std::string_view name) {
  if (name == "astar") return grid_astar_config_schema();
  if (name == "direction-astar") return direction_astar_config_schema();
  if (name == "wpg") return wpg_config_schema();
  return {};
}

std::vector<std::string> local_planner_names() { return {"astar", "direction-astar", "wpg"}; }

std::unique_ptr<LocalPlanner> make_local_planner(std::string_view name, const Config& config) {
  if (name == "astar") return std::make_unique<GridAStarPlanner>(read_grid_astar_config(config));
  if (name == "direction-astar") return std::make_unique<DirectionAStarPlanner>(read_direction_astar_config(config));
  if (name == "wpg") return std::make_unique<WpgPlanner>(read_wpg_config(config));
  std::string names;
  for (const std::string& n : local_planner_names()) names += (names.empty() ? "" : ", ") + n;
  throw ConfigError("", "planning.planner", fmt::format("unknown planner '{}' (known: {})", name, names));
}

Plan plan_outcome(SearchStatus status, std::size_t expanded, double time_s) {
  Plan p;
  p.status = status;
  p.expanded = expanded;
  p.time_s = time_s;
  switch (status) {
    case SearchStatus::kFound:
      p.reason = GuidanceReason::kPathFound;
      break;
    case SearchStatus::kNoPath:
      p.reason = GuidanceReason::kNoPath;
      p.detail = fmt::format("no path: the search exhausted every reachable node ({} expanded)", expanded);
      break;
    case SearchStatus::kExpansionLimit:
      p.reason = GuidanceReason::kSearchLimit;
      p.detail = fmt::format("search stopped at its node limit ({} expansions)", expanded);
      break;
    case SearchStatus::kTimeLimit:
      p.reason = GuidanceReason::kSearchLimit;
      p.detail = fmt::format("search stopped at its time limit ({:.3f} s, {} expansions)", time_s, expanded);
      break;
  }
  return p;
}

double polyline_length(const std::vector<Vec2>& path) {
  double length = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) length += (path[i] - path[i - 1]).norm();
  return length;
}

}  // namespace navaid::planning
