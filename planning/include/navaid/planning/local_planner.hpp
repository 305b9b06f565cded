#pragma once
// The local planners behind one interface: A*, Direction A* and the walking-path generator all
// take a PlanningProblem (maps, start pose, a point goal or a directional subgoal, the estimate's
// position sigma) and return a Plan. `navaid plan`, the Smart Cane Table I reproduction and the
// guidance loop call planners only through this interface (make_local_planner picks by name).
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/mapping/cost_map.hpp"
#include "navaid/mapping/esdf_2d.hpp"
#include "navaid/planning/best_first_search.hpp"
#include "navaid/planning/guidance_command.hpp"

namespace navaid::planning {

using mapping::Vec2;

/// A pose on the ground plane of W: position [m] and heading (yaw about z, 0 = +x) [rad].
struct PlanarPose {
  Vec2 position = Vec2::Zero();
  double yaw_rad = 0.0;
};

struct PlanningProblem {
  const mapping::CostMap* cost = nullptr;  ///< required; its obstacles are cells with cost > threshold
  const mapping::Esdf2d* esdf = nullptr;   ///< required by clearance-based planners (WPG); may be null for A*
  PlanarPose start;
  std::optional<Vec2> goal_W;              ///< a point goal, or
  std::optional<double> goal_direction_rad;///< a directional subgoal: a heading in W (eLabrador)
  /// Horizontal position sigma of the estimate [m]: planners widen their clearance by k sigma.
  double sigma_xy_m = 0.0;
  /// The user's walking speed along start.yaw_rad [m/s] (0: standing). A footstep planner (WPG)
  /// continues a walk in progress instead of planning as if the user could turn on the spot.
  double start_speed_mps = 0.0;
};

struct Plan {
  SearchStatus status = SearchStatus::kNoPath;
  GuidanceReason reason = GuidanceReason::kNoPath;  ///< kPathFound when found, else why not
  std::vector<Vec2> path_W;     ///< start ... end (cell centres or footstep positions)
  std::vector<double> yaw_rad;  ///< heading per path point where the planner has one (WPG), else empty
  std::vector<Vec2> footsteps_W;  ///< the gait points of a footstep planner (WPG), else empty
  double cost = 0.0;            ///< the planner's objective (eq. 11 for Direction A*, eq. 9-10 for WPG)
  double length_m = 0.0;        ///< polyline length of path_W
  std::size_t expanded = 0;     ///< search nodes expanded
  double time_s = 0.0;          ///< search time
  std::string detail;           ///< why there is no path, in words
  bool found() const { return status == SearchStatus::kFound; }
};

class LocalPlanner {
 public:
  virtual ~LocalPlanner() = default;
  virtual std::string_view name() const = 0;
  /// Plans on the problem's maps. Bad problems (no cost map, no goal, missing ESDF for a planner
  /// that needs it) throw navaid::Error; a start or goal off the map or blocked, or no path, is a
  /// Plan without a path whose reason and detail say why.
  virtual Plan plan(const PlanningProblem& problem) const = 0;
};

/// Names: "astar", "direction-astar", "wpg". Reads the planner's keys from `config`
/// (planning.astar.*, planning.direction_astar.*, planning.wpg.*, planning.search.*); throws
/// ConfigError for an unknown name or a key out of range.
std::unique_ptr<LocalPlanner> make_local_planner(std::string_view name, const Config& config);
std::vector<std::string> local_planner_names();

/// Keys planning.search.max_expansions in [1, 1e9] and planning.search.max_time_s in [0, 3600]
/// (0: no time limit, so that replay stays deterministic).
SearchLimits read_search_limits(const Config& config);

/// A Plan with a search's status, counters and, when nothing was found, the reason and detail
/// (no path, node limit, time limit); the planner adds the path when found.
Plan plan_outcome(SearchStatus status, std::size_t expanded, double time_s);

/// Polyline length [m].
double polyline_length(const std::vector<Vec2>& path);

}  // namespace navaid::planning
