#include "navaid/experiments/reach_protocol.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/config_schema.hpp"

namespace navaid::experiments {

namespace {

constexpr double kDeg = M_PI / 180.0;


/// The outward normal of the tagged face, horizontal (the tag's z points into the face).
simulation::Vec2 face_normal(const simulation::TargetObject& t) {
  const Vec3 n = -t.T_W_tag.rotation().col(2);
  return simulation::Vec2(n.x(), n.y()).normalized();
}

}  // namespace

namespace {
const ReachProtocolConfig kDefaults;
const ConfigKey<double> kViewDistance{"trial.reach.view_distance_m", kDefaults.view_distance_m, {0.5, 5.0},
                                      "the person is shown the object from this far [m]"};
const ConfigKey<double> kLocate{"trial.reach.locate_s", kDefaults.locate_s, {0.0, 60.0},
                                "time the device gets to locate the object first [s]"};
const ConfigKey<double> kEscortSpeed{"trial.reach.escort_speed_mps", kDefaults.escort_speed_mps, {0.2, 1.5},
                                     "speed of the escort to the start [m/s]"};
const ConfigKey<double> kStartTurn{"trial.reach.start_turn_deg", kDefaults.start_turn_rad / kDeg, {-180.0, 180.0},
                                   "the person starts turned away from the object by this [deg]"};
const ConfigKey<double> kTimeLimit{"trial.reach.time_limit_s", kDefaults.time_limit_s, {5.0, 3600.0},
                                   "a reach fails after this [s]"};
const ConfigKey<double> kTouch{"trial.reach.touch_m", kDefaults.touch_m, {0.005, 0.3},
                               "the fingers reach this far beyond the hand-worn unit [m]"};
const ConfigKey<double> kGrasp{"trial.reach.grasp_m", kDefaults.grasp_m, {0.01, 0.5},
                               "the object is grasped within this [m]"};
const ConfigKey<double> kRangeSigma{"trial.reach.memory.range_sigma", kDefaults.range_sigma, {0.0, 1.0},
                                    "relative error of the remembered distance to the object"};
const ConfigKey<double> kBearingSigma{"trial.reach.memory.bearing_sigma_deg", kDefaults.bearing_sigma_rad / kDeg,
                                      {0.0, 90.0}, "error of the remembered bearing to the object [deg]"};
const ConfigKey<double> kHeightSigma{"trial.reach.memory.height_sigma_m", kDefaults.height_sigma_m, {0.0, 1.0},
                                     "error of the remembered height of the object [m]"};
const ConfigKey<std::vector<double>> kStartXy{"trial.reach.start_xy", std::nullopt, 2, {-1e4, 1e4},
                                              "the person's start [x, y] in the world [m]; absent: view_distance_m "
                                              "before the object"};
}  // namespace

ConfigSchema reach_protocol_config_schema() {
  return ConfigSchema()
      .add(kViewDistance)
      .add(kLocate)
      .add(kEscortSpeed)
      .add(kStartTurn)
      .add(kTimeLimit)
      .add(kTouch)
      .add(kGrasp)
      .add(kRangeSigma)
      .add(kBearingSigma)
      .add(kHeightSigma)
      .add(kStartXy);
}

ReachProtocolConfig read_reach_protocol_config(const Config& c) {
  ReachProtocolConfig r;
  r.view_distance_m = get(c, kViewDistance);
  r.locate_s = get(c, kLocate);
  r.escort_speed_mps = get(c, kEscortSpeed);
  r.start_turn_rad = get(c, kStartTurn) * kDeg;
  r.time_limit_s = get(c, kTimeLimit);
  r.touch_m = get(c, kTouch);
  r.grasp_m = get(c, kGrasp);
  r.range_sigma = get(c, kRangeSigma);
  r.bearing_sigma_rad = get(c, kBearingSigma) * kDeg;
  r.height_sigma_m = get(c, kHeightSigma);
  if (c.has(kStartXy.name)) {
    const std::vector<double> xy = get(c, kStartXy);
    r.start_xy = simulation::Vec2(xy[0], xy[1]);
  }
  return r;
}

ReachProtocol::ReachProtocol(const simulation::Scenario& scenario, const ReachProtocolConfig& config,
                             const simulation::UserModel& user, const simulation::ReachModel& reach, bool guided,
                             std::uint64_t seed)
    : config_(config), user_(user, reach, seed), guided_(guided), seed_(seed) {
  if (scenario.targets.empty())
    throw ConfigError("", "simulation.targets",
                      "trial.task=reach needs a scenario with an object to reach for (the lab walks, with "
                      "simulation.targets=true); " + scenario.name + " has none");
  target_ = &scenario.targets.front();
  const simulation::Vec2 face = target_->T_W_tag.t.head<2>();
  const simulation::Vec2 n = face_normal(*target_);
  locate_xy_ = face + config_.view_distance_m * n;
  locate_heading_ = std::atan2(-n.y(), -n.x());
  start_xy_ = config_.start_xy.value_or(scenario.path.front());
  const auto& e = scenario.extent;
  if (!e.empty && (start_xy_.x() < e.min.x() || start_xy_.x() > e.max.x() || start_xy_.y() < e.min.y() ||
                   start_xy_.y() > e.max.y()))
    throw ConfigError("", "trial.reach.start_xy", "lies outside scenario " + scenario.name);
  const simulation::Vec2 to = face - start_xy_;
  start_heading_ = wrap_angle(std::atan2(to.y(), to.x()) + config_.start_turn_rad);
}

void ReachProtocol::perceive(const simulation::Instruction& i) {
  if (phase_ == Phase::kSearch && guided_) user_.perceive(i);
}

double ReachProtocol::distance_to_object(const Vec3& p_W) const {
  const simulation::Vec2 n = face_normal(*target_);
  const Mat3 R = Eigen::AngleAxisd(std::atan2(n.y(), n.x()), Vec3::UnitZ()).toRotationMatrix();
  const Vec3 q = (R.transpose() * (p_W - target_->center_W)).cwiseAbs() - target_->half_extents;
  return q.cwiseMax(0.0).norm();
}

simulation::MotionCommand ReachProtocol::decide(double t_s, const simulation::PersonMotion& body,
                                                simulation::HandMotion& hand, double mount_z, bool bumped) {
  simulation::MotionCommand stand;
  stand.heading_rad = body.heading();
  if (phase_ == Phase::kLocate) {
    stand.heading_rad = locate_heading_;
    if (t_s >= config_.locate_s) phase_ = Phase::kEscort;
    return stand;
  }
  if (phase_ == Phase::kEscort) {
    const simulation::Vec2 to = start_xy_ - body.position();
    if (to.norm() > 0.15) {
      stand.heading_rad = std::atan2(to.y(), to.x());
      // Turn first, then walk (a guide leads by the arm); slow down on arrival.
      if (std::abs(wrap_angle(stand.heading_rad - body.heading())) < 0.3)
        stand.speed_mps = std::min(config_.escort_speed_mps, to.norm());
      return stand;
    }
    stand.heading_rad = start_heading_;
    if (std::abs(wrap_angle(body.heading() - start_heading_)) < 3 * kDeg && body.speed() < 0.02 &&
        std::abs(body.yaw_rate()) < 0.05) {
      phase_ = Phase::kSearch;
      search_start_ = t_s;
      if (!guided_) {
        // Where the person believes the object is: what they touched, as it lies from the start.
        std::mt19937_64 rng(seed_ * 0x2545F4914F6CDD1DULL + 3);
        std::normal_distribution<double> n(0.0, 1.0);
        const Vec3& face = target_->T_W_tag.t;
        const simulation::Vec2 to_face = face.head<2>() - start_xy_;
        const double range = to_face.norm() * std::max(0.1, 1.0 + config_.range_sigma * n(rng));
        const double bearing = std::atan2(to_face.y(), to_face.x()) + config_.bearing_sigma_rad * n(rng);
        user_.search_from_memory(Vec3(start_xy_.x() + range * std::cos(bearing), start_xy_.y() + range * std::sin(bearing),
                                      face.z() + config_.height_sigma_m * n(rng)));
      }
    }
    return stand;
  }
  if (phase_ == Phase::kSearch) {
    const simulation::ReachingUser::Decision d = user_.decide(t_s, body, hand, mount_z, bumped);
    grasp_now_ = grasp_now_ || d.grasp;
    return d.body;
  }
  return stand;
}

void ReachProtocol::check(double t_s, const Vec3& hand_W) {
  if (phase_ != Phase::kSearch) return;
  const double d = distance_to_object(hand_W);
  closest_m_ = std::min(closest_m_, d);
  const auto end = [&](bool success, const char* outcome) {
    success_ = success;
    outcome_ = outcome;
    phase_ = Phase::kDone;
    end_s_ = t_s;
  };
  if (d <= config_.touch_m) return end(true, "touched");
  if (grasp_now_) {
    grasp_now_ = false;
    if (d <= config_.grasp_m) return end(true, "grasped");
    ++failed_grasps_;
  }
  if (t_s - *search_start_ >= config_.time_limit_s) end(false, "timeout");
}

double ReachProtocol::search_time_s(double now_s) const {
  if (!search_start_) return 0.0;
  return (phase_ == Phase::kDone ? end_s_ : now_s) - *search_start_;
}

}  // namespace navaid::experiments
