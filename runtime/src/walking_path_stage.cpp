// The Smart Cane's chain (seed smart-cane, §III-D / §IV): toward a goal, the walking-path generator
// re-plans on the newest ESDF at 10 Hz inside the 10 m sensing range, the path is followed with the
// 2 m look-ahead and the PI heading controller (eq. 1) turns the heading error into the steering
// wheel's command. The goal is given in the frame of the pose where guidance starts (the first
// localised estimate): forward and left in metres, from device.goal_start_frame_m or, asked at
// that moment, from the mission (device_mission.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/runtime/guidance_stage.hpp"
#include "navaid/planning/config_schema.hpp"
#include "navaid/runtime/config_schema.hpp"
#include "navaid/planning/smart_cane_guidance.hpp"

namespace navaid::runtime {
namespace {

using mapping::Vec2;

/// The last point of the straight line from `from` to `goal` that is still on the map, half a
/// metre inside its edge (bisection: the map is a rectangle around `from`).
Vec2 toward_map_edge(const Vec2& from, const Vec2& goal, const mapping::GridGeometry& g) {
  const Vec2 d = goal - from;
  const Vec2 inset = 0.5 * d.normalized();
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < 30; ++i) {
    const double mid = 0.5 * (lo + hi);
    (g.contains(g.cell_of(from + mid * d + inset)) ? lo : hi) = mid;
  }
  return from + lo * d;
}

class WalkingPathStage final : public GuidanceStage {
 public:
  explicit WalkingPathStage(const GuidanceStageContext& c)
      : guidance_(planning::read_smart_cane_guidance_config(c.config)),
        goal_start_frame_(c.spec.goal_start_frame_m),
        ask_goal_(c.mission.walking_goal) {
    if (!goal_start_frame_ && !ask_goal_)
      throw Error("device " + c.spec.name + " needs a goal: set device.goal_start_frame_m=FORWARD,LEFT");
  }

  GuidanceOutput update(const GuidanceInput& in) override {
    GuidanceOutput out;
    out.planner = std::string(guidance_.planner());
    const StateEstimate& e = in.estimate;
    const bool localised = e.mode != EstimatorMode::kInitializing && e.mode != EstimatorMode::kLost;
    if (!goal_W_ && localised) goal_W_ = anchor_goal(e);
    if (!goal_W_ || !in.maps) {
      // PathGuidance says "locating" for an unsure estimate; before the goal or the map exist the
      // cane says the same.
      out.command = waiting_command(e.t, planning::GuidanceReason::kLocating,
                                    goal_W_ ? "no local map yet" : fmt::format("estimator {}", to_string(e.mode)));
      return out;
    }
    const std::size_t plans_before = guidance_.chain().stats().plans;
    // A goal beyond the local map (the 10 m sensing range) is a direction to walk in until it
    // comes into range (the generator's horizon).
    planning::Subgoal subgoal;
    const auto& geometry = in.maps->cost.geometry();
    if (geometry.contains(geometry.cell_of(*goal_W_))) {
      subgoal.goal_W = *goal_W_;
    } else if (guidance_.planner() == "astar") {
      // Grid A* takes point goals only: the goal's direction where it leaves the local map.
      subgoal.goal_W = toward_map_edge(e.T_W_B.t.head<2>(), *goal_W_, geometry);
    } else {
      const Vec2 d = *goal_W_ - e.T_W_B.t.head<2>();
      subgoal.direction_rad = std::atan2(d.y(), d.x());
    }
    out.command = guidance_.update(e, in.maps->cost, in.maps->esdf, subgoal);
    if (guidance_.chain().stats().plans > plans_before && guidance_.chain().plan())
      out.new_plan = *guidance_.chain().plan();
    return out;
  }

  nlohmann::ordered_json summary() const override {
    const auto& s = guidance_.chain().stats();
    nlohmann::ordered_json j = {{"planner", guidance_.planner()}, {"updates", s.updates}, {"plans", s.plans},
                                {"plans_failed", s.plans_failed}, {"withheld", s.locating}, {"blocked", s.blocked}};
    if (goal_W_) j["goal_W"] = {goal_W_->x(), goal_W_->y()};
    return j;
  }

 private:
  /// The goal in W from the first localised estimate: forward / left of its pose.
  Vec2 anchor_goal(const StateEstimate& e) const {
    const auto [forward, left] = goal_start_frame_ ? *goal_start_frame_ : ask_goal_(e.t);
    const Vec2 rel(forward, left);
    return e.T_W_B.t.head<2>() + Eigen::Rotation2Dd(planning::body_yaw(e.T_W_B)) * rel;
  }

  planning::SmartCaneGuidance guidance_;
  std::optional<std::pair<double, double>> goal_start_frame_;
  WalkingGoal ask_goal_;  ///< asked once, when guidance starts
  std::optional<Vec2> goal_W_;
};

}  // namespace

ConfigSchema walking_path_stage_schema() { return planning::smart_cane_guidance_config_schema(); }

std::unique_ptr<GuidanceStage> make_walking_path_stage(const GuidanceStageContext& context) {
  return std::make_unique<WalkingPathStage>(context);
}

}  // namespace navaid::runtime
