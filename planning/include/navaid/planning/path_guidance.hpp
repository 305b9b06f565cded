#pragma once
// The eLabrador walking-path chain on every estimate: check that the estimate can be trusted,
// (re)plan with a local planner toward the subgoal, follow the path (Alg. 2) and say where to
// walk. Uncertainty decides what is said:
//   - initializing or lost, or heading sigma above its limit: "wait, locating", no direction;
//   - a route subgoal whose GPS-map registration is too unsure: "wait", registration-uncertain;
//   - position sigma widens the planner's clearance (PlanningProblem::sigma_xy_m) and lowers the
//     command's confidence.
// Re-planning happens when there is no plan, when the plan runs into an obstacle of the new cost
// map (Alg. 2's collision check on the path itself), when the subgoal moved, when the user
// strayed from the path, and at a fixed period (the map changes as the user walks).
#include <memory>
#include <optional>

#include "navaid/core/config.hpp"
#include "navaid/core/state_estimate.hpp"
#include "navaid/mapping/pose_uncertainty.hpp"
#include "navaid/planning/local_planner.hpp"
#include "navaid/planning/path_follower.hpp"

namespace navaid::planning {

/// Where the local planner should lead: a point or a direction in W. A subgoal that came from a
/// route in the geodetic frame depends on the GPS-map registration (from_route).
struct Subgoal {
  std::optional<Vec2> goal_W;
  std::optional<double> direction_rad;  ///< heading in W
  bool from_route = false;
  /// What the user should face on arrival (the destination's landmark, eLabrador §V-A): the
  /// arrival command then carries its bearing (heading_rad, positive left).
  std::optional<Vec2> face_W;
};

struct PathGuidanceConfig {
  PathFollowerConfig follow;
  double max_heading_sigma_rad = 0.2617993878;      ///< 15 deg: the belt's 30 deg sectors stay right
  double max_registration_yaw_sigma_rad = 0.1745329252;  ///< 10 deg
  double max_registration_xy_sigma_m = 3.0;
  double confidence_sigma_xy_m = 1.0;  ///< confidence falls linearly to 0 at this sigma_xy
  mapping::UncertaintyScope scope = mapping::UncertaintyScope::kWindow;  ///< as the mapping gate
  double window_s = 10.0;
  double replan_period_s = 1.0;        ///< re-plan at least this often
  double replan_direction_change_rad = 0.3490658504;  ///< 20 deg
  double replan_goal_shift_m = 1.0;
  double replan_off_path_m = 1.0;      ///< re-plan when the user is further than this from the path
  double arrive_radius_m = 0.5;        ///< point goals: arrived within this distance
};

/// Keys planning.guidance.*: max_heading_sigma_deg, max_registration_yaw_sigma_deg,
/// max_registration_xy_sigma_m, confidence_sigma_xy_m, scope (window | absolute), window_s,
/// replan_period_s, replan_direction_change_deg, replan_goal_shift_m, replan_off_path_m,
/// arrive_radius_m; plus planning.follow.*.
PathGuidanceConfig read_path_guidance_config(const Config& config);

/// Yaw of the body's x axis (forward: DESIGN.md, B is x forward, y left, z up) in W [rad].
double body_yaw(const SE3& T_W_B);

struct PathGuidanceStats {
  std::size_t updates = 0;
  std::size_t plans = 0;        ///< planner calls
  std::size_t plans_failed = 0; ///< calls that returned no path
  std::size_t locating = 0;     ///< commands withheld for uncertainty (locating or registration)
  std::size_t blocked = 0;      ///< stop commands for an obstacle ahead
};

class PathGuidance {
 public:
  PathGuidance(const PathGuidanceConfig& config, std::unique_ptr<LocalPlanner> planner);

  /// One cycle. `esdf` may be null. Throws navaid::Error for a broken covariance.
  GuidanceCommand update(const StateEstimate& estimate, const mapping::CostMap& cost, const mapping::Esdf2d* esdf,
                         const Subgoal& subgoal);

  const std::optional<Plan>& plan() const { return plan_; }
  const PathGuidanceStats& stats() const { return stats_; }

 private:
  bool needs_replan(Timestamp t, const Vec2& p, const mapping::CostMap& cost, const Subgoal& subgoal) const;

  PathGuidanceConfig config_;
  std::unique_ptr<LocalPlanner> planner_;
  mapping::UncertaintyWindow window_;
  std::optional<Plan> plan_;
  Subgoal planned_for_;
  Timestamp planned_at_ = 0;
  PathGuidanceStats stats_;
};

}  // namespace navaid::planning
