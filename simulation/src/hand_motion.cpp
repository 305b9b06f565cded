#include "navaid/simulation/hand_motion.hpp"

#include <algorithm>
#include <stdexcept>

#include "first_order_lag.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/simulation/config_schema.hpp"

namespace navaid::simulation {

namespace {

Vec3 read_vec3(const Config& c, const ConfigKey<std::vector<double>>& key) {
  const std::vector<double> v = get(c, key);
  return Vec3(v[0], v[1], v[2]);
}

std::vector<double> items(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

const HandMotionConfig kDefaults;
const ConfigKey<double> kSpeed{"user.hand.speed_mps", kDefaults.speed_mps, {0.02, 2.0},
                               "the simulated hand's speed toward a new place [m/s]"};
const ConfigKey<double> kMaxAcceleration{"user.hand.max_acceleration_mps2", kDefaults.max_acceleration_mps2, {0.1, 20.0},
                                         "the simulated hand's largest acceleration [m/s^2]"};
const ConfigKey<std::vector<double>> kRestOffset{"user.hand.rest_offset_m", items(kDefaults.rest_offset_m), 3,
                                                 {-2.0, 2.0}, "the hand's rest place relative to the body [m]"};
const ConfigKey<std::vector<double>> kMinOffset{"user.hand.min_offset_m", items(kDefaults.min_offset_m), 3, {-2.0, 2.0},
                                                "lower corner of the hand's reach relative to the body [m]"};
const ConfigKey<std::vector<double>> kMaxOffset{"user.hand.max_offset_m", items(kDefaults.max_offset_m), 3, {-2.0, 2.0},
                                                "upper corner of the hand's reach relative to the body [m]"};

}  // namespace

ConfigSchema hand_motion_config_schema() {
  return ConfigSchema().add(kSpeed).add(kMaxAcceleration).add(kRestOffset).add(kMinOffset).add(kMaxOffset);
}

HandMotionConfig read_hand_motion_config(const Config& c) {
  HandMotionConfig h;
  h.speed_mps = get(c, kSpeed);
  h.max_acceleration_mps2 = get(c, kMaxAcceleration);
  h.rest_offset_m = read_vec3(c, kRestOffset);
  h.min_offset_m = read_vec3(c, kMinOffset);
  h.max_offset_m = read_vec3(c, kMaxOffset);
  for (int i = 0; i < 3; ++i)
    if (!(h.min_offset_m[i] < h.max_offset_m[i]) || h.rest_offset_m[i] < h.min_offset_m[i] ||
        h.rest_offset_m[i] > h.max_offset_m[i])
      throw ConfigError(c.origin("user.hand.rest_offset_m"), "user.hand.rest_offset_m",
                        "must lie within user.hand.min_offset_m and user.hand.max_offset_m (min < max) on every axis");
  return h;
}

HandMotion::HandMotion(const HandMotionConfig& config)
    : config_(config), o_(config.rest_offset_m), target_(config.rest_offset_m) {}

void HandMotion::move_to(const Vec3& offset) {
  target_ = offset.cwiseMax(config_.min_offset_m).cwiseMin(config_.max_offset_m);
}

bool HandMotion::at_limit(int axis, double sign, double tolerance_m) const {
  return sign > 0 ? o_[axis] >= config_.max_offset_m[axis] - tolerance_m
                  : o_[axis] <= config_.min_offset_m[axis] + tolerance_m;
}

void HandMotion::step(double dt) {
  if (!(dt > 0)) throw std::invalid_argument("HandMotion::step: dt must be positive");
  // The velocity wanted: toward the target at the hand's speed (its direction kept across the
  // axes), slowing within speed x tau of it.
  const Vec3 to_go = target_ - o_;
  Vec3 wanted = to_go / config_.position_time_constant_s;
  if (wanted.norm() > config_.speed_mps) wanted *= config_.speed_mps / wanted.norm();
  for (int i = 0; i < 3; ++i)
    a_[i] = lag_rate(v_[i], wanted[i], config_.velocity_time_constant_s, config_.max_acceleration_mps2, dt);
  o_ += v_ * dt + 0.5 * a_ * dt * dt;
  v_ += a_ * dt;
}

KinematicState HandMotion::compose(const KinematicState& body, double psi, double r, double rdot) const {
  const Mat3 R = Eigen::AngleAxisd(psi, Vec3::UnitZ()).toRotationMatrix();
  const Vec3 z = Vec3::UnitZ();
  KinematicState s = body;
  s.T_W_B.t = body.T_W_B.t + R * o_;
  s.v_W = body.v_W + R * (v_ + r * z.cross(o_));
  s.a_W = body.a_W + R * (a_ + 2.0 * r * z.cross(v_) + rdot * z.cross(o_) + r * r * z.cross(z.cross(o_)));
  return s;
}

Vec3 HandMotion::position_W(const Vec2& position, double z, double psi) const {
  const Mat3 R = Eigen::AngleAxisd(psi, Vec3::UnitZ()).toRotationMatrix();
  return Vec3(position.x(), position.y(), z) + R * o_;
}

}  // namespace navaid::simulation
