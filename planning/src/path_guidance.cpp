#include "navaid/planning/path_guidance.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "navaid/core/errors.hpp"
#include "navaid/planning/angles.hpp"
#include "navaid/planning/config_schema.hpp"

namespace navaid::planning {

namespace {
const PathGuidanceConfig kPathGuidanceDefaults;
const ConfigKey<double> kPathGuidanceMaxHeadingSigma{"planning.guidance.max_heading_sigma_deg",
                                         rad_to_deg(kPathGuidanceDefaults.max_heading_sigma_rad), {0.1, 180.0},
                                         "guidance waits (locating) while the heading sigma exceeds this [deg]"};
const ConfigKey<double> kMaxRegistrationYawSigma{"planning.guidance.max_registration_yaw_sigma_deg",
                                                 rad_to_deg(kPathGuidanceDefaults.max_registration_yaw_sigma_rad), {0.1, 180.0},
                                                 "guidance waits while the GPS-map registration's yaw sigma exceeds "
                                                 "this [deg]"};
const ConfigKey<double> kMaxRegistrationXySigma{"planning.guidance.max_registration_xy_sigma_m",
                                                kPathGuidanceDefaults.max_registration_xy_sigma_m, {0.01, 1000.0},
                                                "guidance waits while the registration's position sigma exceeds this "
                                                "[m]"};
const ConfigKey<double> kConfidenceSigmaXy{"planning.guidance.confidence_sigma_xy_m", kPathGuidanceDefaults.confidence_sigma_xy_m,
                                           {0.01, 100.0}, "guidance confidence falls linearly to 0 at this sigma_xy [m]"};
const ConfigKey<std::string> kPathGuidanceScope{"planning.guidance.scope", std::string("window"), {"window", "absolute"},
                                    "judge the uncertainty gained over the window or the absolute one (as the "
                                    "mapping gate)"};
const ConfigKey<double> kPathGuidanceWindow{"planning.guidance.window_s", kPathGuidanceDefaults.window_s, {0.1, 3600.0},
                                "scope window of the guidance's uncertainty [s]"};
const ConfigKey<double> kReplanPeriod{"planning.guidance.replan_period_s", kPathGuidanceDefaults.replan_period_s, {0.01, 3600.0},
                                      "re-plan at least this often [s] (the Smart Cane's guidance: 0.1 when absent)"};
const ConfigKey<double> kReplanDirectionChange{"planning.guidance.replan_direction_change_deg",
                                               rad_to_deg(kPathGuidanceDefaults.replan_direction_change_rad), {0.1, 180.0},
                                               "re-plan when the goal direction turned by this [deg]"};
const ConfigKey<double> kReplanGoalShift{"planning.guidance.replan_goal_shift_m", kPathGuidanceDefaults.replan_goal_shift_m,
                                         {0.01, 100.0}, "re-plan when the goal moved this far [m]"};
const ConfigKey<double> kReplanOffPath{"planning.guidance.replan_off_path_m", kPathGuidanceDefaults.replan_off_path_m,
                                       {0.05, 100.0}, "re-plan when the user is further than this from the path [m]"};
const ConfigKey<double> kArriveRadius{"planning.guidance.arrive_radius_m", kPathGuidanceDefaults.arrive_radius_m, {0.01, 100.0},
                                      "point goals: arrived within this distance [m]"};
}  // namespace

ConfigSchema path_guidance_config_schema() {
  return path_follower_config_schema()
      .add(kPathGuidanceMaxHeadingSigma)
      .add(kMaxRegistrationYawSigma)
      .add(kMaxRegistrationXySigma)
      .add(kConfidenceSigmaXy)
      .add(kPathGuidanceScope)
      .add(kPathGuidanceWindow)
      .add(kReplanPeriod)
      .add(kReplanDirectionChange)
      .add(kReplanGoalShift)
      .add(kReplanOffPath)
      .add(kArriveRadius);
}

PathGuidanceConfig read_path_guidance_config(const Config& config) {
  PathGuidanceConfig c;
  c.follow = read_path_follower_config(config);
  c.max_heading_sigma_rad = deg_to_rad(get(config, kPathGuidanceMaxHeadingSigma));
  c.max_registration_yaw_sigma_rad = deg_to_rad(get(config, kMaxRegistrationYawSigma));
  c.max_registration_xy_sigma_m = get(config, kMaxRegistrationXySigma);
  c.confidence_sigma_xy_m = get(config, kConfidenceSigmaXy);
  c.scope = get(config, kPathGuidanceScope) == "window" ? mapping::UncertaintyScope::kWindow : mapping::UncertaintyScope::kAbsolute;
  c.window_s = get(config, kPathGuidanceWindow);
  c.replan_period_s = get(config, kReplanPeriod);
  c.replan_direction_change_rad = deg_to_rad(get(config, kReplanDirectionChange));
  c.replan_goal_shift_m = get(config, kReplanGoalShift);
  c.replan_off_path_m = get(config, kReplanOffPath);
  c.arrive_radius_m = get(config, kArriveRadius);
  return c;
}

double body_yaw(const SE3& T_W_B) {
  const Vec3 forward = T_W_B.q * Vec3::UnitX();
  return std::atan2(forward.y(), forward.x());
}

PathGuidance::PathGuidance(const PathGuidanceConfig& config, std::unique_ptr<LocalPlanner> planner)
    : config_(config), planner_(std::move(planner)) {
  if (!planner_) throw Error("path guidance needs a local planner");
}

bool PathGuidance::needs_replan(Timestamp t, const Vec2& p, const mapping::CostMap& cost, const Subgoal& subgoal) const {
  if (!plan_ || !plan_->found() || plan_->path_W.empty()) return true;
  if (ns_to_seconds(t - planned_at_) >= config_.replan_period_s) return true;
  if (subgoal.direction_rad.has_value() != planned_for_.direction_rad.has_value() ||
      subgoal.goal_W.has_value() != planned_for_.goal_W.has_value()) {
    return true;
  }
  if (subgoal.direction_rad &&
      std::abs(wrap_angle(*subgoal.direction_rad - *planned_for_.direction_rad)) > config_.replan_direction_change_rad) {
    return true;
  }
  if (subgoal.goal_W && (*subgoal.goal_W - *planned_for_.goal_W).norm() > config_.replan_goal_shift_m) return true;
  // The plan runs into an obstacle of the current map, or the user left it.
  double nearest = 1e300;
  for (const Vec2& q : plan_->path_W) nearest = std::min(nearest, (q - p).squaredNorm());
  if (std::sqrt(nearest) > config_.replan_off_path_m) return true;
  for (std::size_t i = 1; i < plan_->path_W.size(); ++i) {
    if (first_obstacle_along(cost, plan_->path_W[i - 1], plan_->path_W[i])) return true;
  }
  return false;
}

GuidanceCommand PathGuidance::update(const StateEstimate& estimate, const mapping::CostMap& cost,
                                     const mapping::Esdf2d* esdf, const Subgoal& subgoal) {
  ++stats_.updates;
  GuidanceCommand cmd;
  cmd.t = estimate.t;
  const auto withhold = [&](GuidanceReason reason, std::string detail) {
    ++stats_.locating;
    cmd.action = GuidanceAction::kWait;
    cmd.reason = reason;
    cmd.confidence = 0.0;
    cmd.detail = std::move(detail);
    return cmd;
  };
  if (estimate.mode == EstimatorMode::kInitializing || estimate.mode == EstimatorMode::kLost) {
    return withhold(GuidanceReason::kLocating, fmt::format("estimator {}", to_string(estimate.mode)));
  }
  const mapping::PoseUncertainty absolute = mapping::pose_uncertainty(estimate);
  const mapping::PoseUncertainty windowed = window_.add(estimate.t, absolute, config_.window_s);
  const mapping::PoseUncertainty& u = config_.scope == mapping::UncertaintyScope::kWindow ? windowed : absolute;
  if (u.sigma_yaw > config_.max_heading_sigma_rad) {
    return withhold(GuidanceReason::kLocating, fmt::format("heading sigma {:.1f} deg > {:.1f} deg",
                                                           rad_to_deg(u.sigma_yaw),
                                                           rad_to_deg(config_.max_heading_sigma_rad)));
  }
  if (subgoal.from_route) {
    if (!estimate.T_ENU_W || !estimate.T_ENU_W_covariance) {
      return withhold(GuidanceReason::kRegistrationUncertain, "no GPS-map registration yet");
    }
    const Mat4& c = *estimate.T_ENU_W_covariance;
    const double yaw_sigma = std::sqrt(std::max(0.0, c(0, 0)));
    const double xy_sigma = std::sqrt(std::max(0.0, 0.5 * (c(1, 1) + c(2, 2)) +
                                                       std::sqrt(0.25 * (c(1, 1) - c(2, 2)) * (c(1, 1) - c(2, 2)) +
                                                                 c(1, 2) * c(2, 1))));
    if (!std::isfinite(yaw_sigma) || yaw_sigma > config_.max_registration_yaw_sigma_rad ||
        !std::isfinite(xy_sigma) || xy_sigma > config_.max_registration_xy_sigma_m) {
      return withhold(GuidanceReason::kRegistrationUncertain,
                      fmt::format("GPS-map registration sigma yaw {:.1f} deg, xy {:.2f} m", rad_to_deg(yaw_sigma),
                                  xy_sigma));
    }
  }
  if (!subgoal.goal_W && !subgoal.direction_rad) throw Error("path guidance: the subgoal has neither a point nor a direction");

  const Vec2 p = estimate.T_W_B.t.head<2>();
  const double yaw = body_yaw(estimate.T_W_B);
  if (subgoal.goal_W && (*subgoal.goal_W - p).norm() <= config_.arrive_radius_m) {
    cmd.action = GuidanceAction::kArrived;
    cmd.reason = GuidanceReason::kPathFound;
    cmd.confidence = 1.0;
    cmd.detail = "within the arrival radius of the goal";
    if (subgoal.face_W && (*subgoal.face_W - p).norm() > 1e-6) {
      const Vec2 d = *subgoal.face_W - p;
      cmd.heading_rad = wrap_angle(std::atan2(d.y(), d.x()) - yaw);
      cmd.detail += fmt::format("; the landmark at {:.0f} deg", rad_to_deg(*cmd.heading_rad));
    }
    return cmd;
  }
  if (needs_replan(estimate.t, p, cost, subgoal)) {
    PlanningProblem problem;
    problem.cost = &cost;
    problem.esdf = esdf;
    problem.start = PlanarPose{p, yaw};
    problem.goal_W = subgoal.goal_W;
    problem.goal_direction_rad = subgoal.direction_rad;
    problem.sigma_xy_m = u.sigma_xy;
    problem.start_speed_mps = std::max(0.0, estimate.v_W.head<2>().dot(Vec2(std::cos(yaw), std::sin(yaw))));
    plan_ = planner_->plan(problem);
    planned_for_ = subgoal;
    planned_at_ = estimate.t;
    ++stats_.plans;
    if (!plan_->found()) ++stats_.plans_failed;
  }
  if (!plan_->found()) {
    cmd.action = GuidanceAction::kStop;
    cmd.reason = plan_->reason;
    cmd.confidence = 0.0;
    cmd.detail = plan_->detail;
    return cmd;
  }
  const FollowStep step = follow_path(p, plan_->path_W, cost, config_.follow);
  const double sure = std::clamp(1.0 - u.sigma_xy / config_.confidence_sigma_xy_m, 0.0, 1.0) *
                      std::clamp(1.0 - u.sigma_yaw / config_.max_heading_sigma_rad, 0.0, 1.0);
  if (step.blocked) {
    ++stats_.blocked;
    cmd.action = GuidanceAction::kStop;
    cmd.reason = GuidanceReason::kObstacleAhead;
    cmd.confidence = sure;
    cmd.lookahead_m = step.foresight_m;
    cmd.detail = fmt::format("obstacle {:.2f} m ahead on the way to the path", step.foresight_m);
    plan_.reset();  // re-plan next cycle: the map may show a way around
    return cmd;
  }
  cmd.action = GuidanceAction::kGo;
  cmd.reason = GuidanceReason::kPathFound;
  cmd.heading_rad = wrap_angle(std::atan2(step.direction_W.y(), step.direction_W.x()) - yaw);
  cmd.lookahead_m = step.direction_W.norm();
  cmd.confidence = sure * std::clamp(step.foresight_m / config_.follow.foresight_m, 0.0, 1.0);
  return cmd;
}

}  // namespace navaid::planning
