#include "navaid/simulation/person_motion.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "navaid/core/errors.hpp"
#include "first_order_lag.hpp"

namespace navaid::simulation {

namespace {

constexpr double kTwoPi = 2.0 * M_PI;


void require_motion_field(bool ok, const char* field, const char* range) {
  if (!ok) throw ConfigError("", std::string("user.motion.") + field, std::string("must be ") + range);
}

}  // namespace

void validate(const PersonMotionConfig& c) {
  require_motion_field(c.mount_height_m > 0 && c.mount_height_m < 3, "mount_height_m", "in (0, 3) m");
  require_motion_field(std::isfinite(c.ground_z_m), "ground_z_m", "finite");
  require_motion_field(c.speed_time_constant_s > 0, "speed_time_constant_s", "> 0");
  require_motion_field(c.max_acceleration_mps2 > 0, "max_acceleration_mps2", "> 0");
  require_motion_field(c.heading_gain_per_s > 0, "heading_gain_per_s", "> 0");
  require_motion_field(c.max_turn_rate_rad_s > 0, "max_turn_rate_rad_s", "> 0");
  require_motion_field(c.turn_time_constant_s > 0, "turn_time_constant_s", "> 0");
  require_motion_field(c.max_yaw_acceleration_rad_s2 > 0, "max_yaw_acceleration_rad_s2", "> 0");
  require_motion_field(c.step_length_m > 0.1 && c.step_length_m < 2, "step_length_m", "in (0.1, 2) m");
  require_motion_field(c.bob_amplitude_m >= 0 && c.bob_amplitude_m < 0.2, "bob_amplitude_m", "in [0, 0.2) m");
  require_motion_field(c.scan_amplitude_rad >= 0 && c.scan_amplitude_rad < 1.6, "scan_amplitude_rad", "in [0, 1.6) rad");
  require_motion_field(c.scan_period_s > 0, "scan_period_s", "> 0");
  require_motion_field(c.veer_sigma >= 0, "veer_sigma", ">= 0");
  require_motion_field(c.veer_time_constant_s > 0, "veer_time_constant_s", "> 0");
}

PersonMotion::PersonMotion(const PersonMotionConfig& config, const Vec2& position, double heading_rad,
                           std::uint64_t seed)
    : config_(config), rng_(seed), p_(position), psi_(wrap_angle(heading_rad)) {
  validate(config_);
}

void PersonMotion::step(const MotionCommand& c, double dt) {
  if (!(dt > 0)) throw std::invalid_argument("PersonMotion::step: dt must be positive");
  if (!(c.speed_mps >= 0) || !std::isfinite(c.speed_mps))
    throw std::invalid_argument("PersonMotion::step: speed must be finite and >= 0");
  const PersonMotionConfig& k = config_;
  impact_a_ = Vec2::Zero();
  last_dt_ = dt;
  if (c.new_direction) veer_ = 0;
  const double r_target =
      c.follow_heading ? std::clamp(k.heading_gain_per_s * wrap_angle(c.heading_rad + (c.speed_mps > 0 ? veer_ : 0.0) - psi_),
                                    -k.max_turn_rate_rad_s,
                                    k.max_turn_rate_rad_s)
                       : std::clamp(c.turn_rate_rad_s, -k.max_turn_rate_rad_s, k.max_turn_rate_rad_s);
  du_ = lag_rate(u_, c.speed_mps, k.speed_time_constant_s, k.max_acceleration_mps2, dt);
  dr_ = lag_rate(r_, r_target, k.turn_time_constant_s, k.max_yaw_acceleration_rad_s2, dt);
  // The veer is a drift of the walked line: one standing still holds the heading they turned to.
  // u, r and psi are polynomials over the step; the position integrates (u cos psi, u sin psi) by
  // Simpson's rule on 8 panels (error ~1e-12 m per 5 ms step at walking speeds).
  const auto heading_at = [&](double s) { return psi_ + r_ * s + 0.5 * dr_ * s * s; };
  const auto velocity_at = [&](double s) {
    const double u = u_ + du_ * s, a = heading_at(s);
    return Vec2(u * std::cos(a), u * std::sin(a));
  };
  constexpr int kPanels = 8;
  const double h = dt / kPanels;
  Vec2 sum = velocity_at(0) + velocity_at(dt);
  for (int i = 1; i < kPanels; ++i) sum += (i % 2 ? 4.0 : 2.0) * velocity_at(i * h);
  p_ += sum * (h / 3.0);
  const double distance = u_ * dt + 0.5 * du_ * dt * dt;
  walked_ += distance;
  gait_phase_ = std::fmod(gait_phase_ + kTwoPi * distance / k.step_length_m, kTwoPi);
  psi_ = wrap_angle(heading_at(dt));
  u_ = std::max(0.0, u_ + du_ * dt);
  r_ += dr_ * dt;
  if (k.veer_sigma > 0 && u_ > 0.05)
    veer_ += -veer_ * dt / k.veer_time_constant_s + k.veer_sigma * std::sqrt(dt) * normal_(rng_);
  t_ += dt;
}

void PersonMotion::halt_at(const Vec2& position) {
  if (last_dt_ > 0) impact_a_ = -u_ * Vec2(std::cos(psi_), std::sin(psi_)) / last_dt_;
  p_ = position;
  u_ = 0;
  du_ = 0;
}

KinematicState PersonMotion::state() const {
  const PersonMotionConfig& k = config_;
  const double w = kTwoPi / k.scan_period_s;
  const double scan = k.scan_amplitude_rad * std::sin(w * t_);
  const double scan_rate = k.scan_amplitude_rad * w * std::cos(w * t_);
  const double scan_accel = -k.scan_amplitude_rad * w * w * std::sin(w * t_);
  const double phase_rate = kTwoPi * u_ / k.step_length_m, phase_accel = kTwoPi * du_ / k.step_length_m;
  const Vec2 tangent(std::cos(psi_), std::sin(psi_)), normal(-std::sin(psi_), std::cos(psi_));
  KinematicState s;
  const double yaw = psi_ + scan;
  s.T_W_B = SE3(Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ())),
                Vec3(p_.x(), p_.y(), k.ground_z_m + k.mount_height_m + k.bob_amplitude_m * std::sin(gait_phase_)));
  const Vec2 v = u_ * tangent, a = du_ * tangent + u_ * r_ * normal;
  s.v_W = Vec3(v.x(), v.y(), k.bob_amplitude_m * std::cos(gait_phase_) * phase_rate);
  s.a_W = Vec3(a.x() + impact_a_.x(), a.y() + impact_a_.y(),
               k.bob_amplitude_m * (std::cos(gait_phase_) * phase_accel - std::sin(gait_phase_) * phase_rate * phase_rate));
  s.omega_B = Vec3(0, 0, r_ + scan_rate);
  s.alpha_B = Vec3(0, 0, dr_ + scan_accel);
  return s;
}

}  // namespace navaid::simulation
