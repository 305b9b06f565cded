#pragma once
// W-ROMA's object-reach trial (seed w-roma-rgbd-vio-object-manipulation §VI-B) for `navaid
// trial` (trial.task=reach; docs/simulated-users.md "Reaching"):
//   locate  the person stands view_distance_m before the object's tagged face, facing it, for
//           locate_s (the device finds the object and its estimator starts);
//   escort  a sighted guide leads them to the navigation start (start_xy, else the scenario's
//           first waypoint)
//           and turns them start_turn_deg left of the object, out of the camera's view; no
//           contacts are counted, nothing the device says is acted on;
//   search  timed from here: guided by the hand unit, or from memory (the object remembered with
//           memory errors drawn from the seed: range x (1 + N(0, range_sigma)), bearing +
//           N(0, bearing_sigma), height + N(0, height_sigma), from the start). Success: the hand
//           touches the object (within touch_m of its box) or grasps it (within grasp_m on "target
//           reached") before time_limit_s (the paper: 2 minutes).
#include <cstdint>
#include <optional>
#include <string>

#include "navaid/core/config.hpp"
#include "navaid/simulation/hand_motion.hpp"
#include "navaid/simulation/reaching_user.hpp"
#include "navaid/simulation/scenario.hpp"

namespace navaid::experiments {

struct ReachProtocolConfig {
  double view_distance_m = 2.0;
  double locate_s = 6.0;
  double escort_speed_mps = 0.6;
  double start_turn_rad = 60.0 * M_PI / 180.0;
  double time_limit_s = 120.0;
  double touch_m = 0.08;  ///< the fingers reach this far beyond the hand-worn unit
  double grasp_m = 0.12;
  double range_sigma = 0.15;
  double bearing_sigma_rad = 15.0 * M_PI / 180.0;
  double height_sigma_m = 0.08;
  /// The navigation start (W); unset: the scenario's first waypoint.
  std::optional<simulation::Vec2> start_xy;
};

/// Keys trial.reach.*: view_distance_m [0.5, 5], locate_s [0, 60], escort_speed_mps [0.2, 1.5],
/// start_turn_deg [-180, 180], time_limit_s [5, 3600], touch_m [0.005, 0.3], grasp_m [0.01, 0.5],
/// memory.range_sigma [0, 1], memory.bearing_sigma_deg [0, 90], memory.height_sigma_m [0, 1],
/// start_xy [x, y] (m, W).
ReachProtocolConfig read_reach_protocol_config(const Config& config);

class ReachProtocol {
 public:
  enum class Phase { kLocate, kEscort, kSearch, kDone };

  /// Needs a scenario with a target object (ConfigError on key simulation.targets otherwise).
  /// `guided`: the person follows the hand unit; otherwise searches from memory.
  ReachProtocol(const simulation::Scenario& scenario, const ReachProtocolConfig& config,
                const simulation::UserModel& user, const simulation::ReachModel& reach, bool guided,
                std::uint64_t seed);

  simulation::Vec2 start_position() const { return locate_xy_; }
  double start_heading() const { return locate_heading_; }
  Phase phase() const { return phase_; }
  const ReachProtocolConfig& config() const { return config_; }

  /// A cue the device gave; heard only while searching.
  void perceive(const simulation::Instruction& i);
  /// The next step at time t (t < 0: the still start). `bumped`: the body ran into something.
  simulation::MotionCommand decide(double t_s, const simulation::PersonMotion& body, simulation::HandMotion& hand,
                                   double mount_z, bool bumped);
  /// After the step: ends the search on a touch, a grasp or the time limit. The hand's point in W.
  void check(double t_s, const Vec3& hand_W);

  bool success() const { return success_; }
  const std::string& outcome() const { return outcome_; }
  std::optional<double> search_start_s() const { return search_start_; }
  /// Seconds from the start of the search to its end (or to now).
  double search_time_s(double now_s) const;
  std::size_t failed_grasps() const { return failed_grasps_; }
  double closest_m() const { return closest_m_; }
  const simulation::ReachCounts& counts() const { return user_.counts(); }
  /// Distance from a point to the object's box [m] (0 inside).
  double distance_to_object(const Vec3& p_W) const;

 private:
  const simulation::TargetObject* target_;
  ReachProtocolConfig config_;
  simulation::ReachingUser user_;
  bool guided_;
  std::uint64_t seed_;
  simulation::Vec2 locate_xy_, start_xy_;
  double locate_heading_ = 0, start_heading_ = 0;
  Phase phase_ = Phase::kLocate;
  std::optional<double> search_start_;
  double end_s_ = 0;
  bool grasp_now_ = false, success_ = false;
  std::string outcome_ = "unfinished";
  std::size_t failed_grasps_ = 0;
  double closest_m_ = 1e9;
};

}  // namespace navaid::experiments
